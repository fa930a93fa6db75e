#pragma once
// Sample-point (variable-kernel) density estimates: every photon carries its own radius r_i
// (photon/map/photon_radii.h) and spreads its power over its own ball or disc, instead of the balloon
// estimates of estimators.h, where the query's k-th neighbour sets one radius for all. These are
// the estimates behind the beam radiance estimate; docs/beam_estimate.md derives why they need no
// k-1 factor: E = density exactly, for every k >= 1, with any normalised kernel.
//
// Brute force over the photons given (the caller passes candidates, e.g. from a BVH of the balls):
//   point (3D):  S(x)   = sum_i w_i K(|x - x_i| / r_i) / (n_3 4/3 pi r_i^3)        over |x - x_i| < r_i
//   beam  (2D):  B(ray) = sum_i w_i K(d_i / r_i) / (n_2 pi r_i^2)                  over d_i < r_i
// where d_i is the distance from x_i to the segment's line, for photons whose foot point lies on
// the segment [0, tmax]. B estimates the line integral of the density along the segment.
#include <vector>

#include "core/math.h"
#include "photon/estimate/kernels.h"

namespace vpm {

struct SamplePoint {
    Vec3 position;
    double radius;   // r_i
    double weight;   // w_i (one channel; the renderer applies it per channel)
};

inline double sample_point_density(const Vec3& x, const std::vector<SamplePoint>& points, const Kernel& kernel) {
    double s = 0.0;
    for (const SamplePoint& p : points) {
        const double d2 = (x - p.position).squaredNorm(), r2 = p.radius * p.radius;
        if (!(d2 < r2)) continue;
        s += p.weight * kernel.weight(d2 / r2, 3) / (4.0 / 3.0 * kPi * r2 * p.radius);
    }
    return s;
}

// `dir` unit length.
inline double beam_line_density(const Vec3& origin, const Vec3& dir, double tmax, const std::vector<SamplePoint>& points,
                                const Kernel& kernel) {
    double s = 0.0;
    for (const SamplePoint& p : points) {
        const Vec3 v = p.position - origin;
        const double t = v.dot(dir);
        if (t < 0.0 || t > tmax) continue;
        const double d2 = std::max(0.0, v.squaredNorm() - t * t), r2 = p.radius * p.radius;
        if (!(d2 < r2)) continue;
        s += p.weight * kernel.weight(d2 / r2, 2) / (kPi * r2);
    }
    return s;
}

}  // namespace vpm
