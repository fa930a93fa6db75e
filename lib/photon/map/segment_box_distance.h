#pragma once
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

}  // namespace vpm
