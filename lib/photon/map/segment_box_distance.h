#pragma once
// Segment-box tests for the photon-beam BVH's k-nearest query (photon/map/photon_beam_bvh.h).
// The max-norm distance from a segment o + t d, t in [0, tmax], to an axis-aligned box: the
// smallest r >= 0 for which the box grown by r on every side meets the segment. It is a lower
// bound of the Euclidean distance (|x|_inf <= |x|_2), so a BVH query for everything within
// Euclidean distance r of the segment may skip a box whose value exceeds r; the photon-beam BVH's
// best-first k-nearest traversal orders its nodes by it (photon/map/photon_beam_bvh.h).
//
// Closed form. Along an axis a with d_a != 0 the segment is within r of the slab [lo_a, hi_a] for
// t in [(A_a - r) / |d_a|, (B_a + r) / |d_a|], A_a and B_a the signed distances along the travel
// direction to the near and far planes. The grown box meets the segment when the largest lower end
// (with 0) is at most the smallest upper end (with tmax), i.e. when every pair of a lower and an
// upper end is ordered; each pair is linear in r, so r is the largest of the pairs' thresholds.
// Written without dividing by d_a, so nearly axis-parallel segments do not overflow.
#include <algorithm>
#include <cmath>

#include "core/math.h"

namespace vpm {

inline double segment_box_distance_max_norm(const Bounds3& box, const Vec3& o, const Vec3& d, double tmax) {
    double r = 0.0;
    double near[3], far[3], speed[3];
    int moving = 0;
    for (int a = 0; a < 3; ++a) {
        if (d[a] == 0.0) {   // the segment keeps its coordinate: the slab's distance, for every t
            r = std::max({r, box.lo[a] - o[a], o[a] - box.hi[a]});
            continue;
        }
        const bool up = d[a] > 0.0;
        near[moving] = up ? box.lo[a] - o[a] : o[a] - box.hi[a];
        far[moving] = up ? box.hi[a] - o[a] : o[a] - box.lo[a];
        speed[moving] = std::abs(d[a]);
        ++moving;
    }
    for (int i = 0; i < moving; ++i) {
        // Lower end of axis i against t <= tmax, and t >= 0 against the upper end of axis i.
        if (std::isfinite(tmax)) r = std::max(r, near[i] - tmax * speed[i]);
        r = std::max(r, -far[i]);
        for (int j = 0; j < moving; ++j)
            if (j != i) r = std::max(r, (near[i] * speed[j] - far[j] * speed[i]) / (speed[i] + speed[j]));
    }
    return r;
}

// A lower bound of the Euclidean distance from any point of the box to the line o + t d (d unit
// length): the distance from the box's centre to the line less the half-diagonal. A crossing's u
// is the distance from a point of the beam (inside the box) to a point of the line, so it is at
// least this; tighter than the max-norm bound across oblique lines, looser along elongated boxes,
// and the query takes the larger of the two.
inline double box_line_distance_sphere(const Bounds3& box, const Vec3& o, const Vec3& d) {
    const Vec3 e = 0.5 * (box.lo + box.hi) - o;
    return std::max(0.0, (e - e.dot(d) * d).norm() - 0.5 * (box.hi - box.lo).norm());
}

// Whether the box meets the slab 0 <= (x - o).d <= tmax (d unit length) between the planes through
// the segment's ends normal to it. A beam crosses the segment at t* in [0, tmax] with its own
// closest point at o + t* d + u n (n normal to d), inside that slab, so a box holding the beam's
// piece must meet it: a filter beside the distance above, whose max-norm ball around a short
// segment is a cube of side 2r where the crossings lie in a disc of thickness tmax. The slack
// keeps a box whose crossing falls on a plane to rounding.
inline bool box_meets_segment_slab(const Bounds3& box, const Vec3& o, const Vec3& d, double tmax) {
    const Vec3 centre = 0.5 * (box.lo + box.hi), half = 0.5 * (box.hi - box.lo);
    const double s = (centre - o).dot(d), h = half.cwiseAbs().dot(d.cwiseAbs());
    const double slack = 1e-9 * (std::abs(s) + h + (std::isfinite(tmax) ? tmax : 0.0));
    return s + h >= -slack && (!std::isfinite(tmax) || s - h <= tmax + slack);
}

}  // namespace vpm
