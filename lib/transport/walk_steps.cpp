#include "transport/walk_steps.h"

namespace vpm {

namespace {
// Offset for rays leaving a surface. Positions are double and Embree sees float coordinates
// relative to the scene's centre (surfaces.cpp, which also skips self-hits by the refined double
// distance), so the offset must not grow with the distance from the origin: 1e-4 * |p| moved
// spawned rays 100 units at 1e6 (found by the translated cells of `vpm stress`). A fixed 1e-4
// plus ~2^22 double ulps of |p| keeps the origin on the right side anywhere.
double surface_epsilon(const Vec3& p) { return 1e-4 + 1e-9 * p.cwiseAbs().maxCoeff(); }
}  // namespace

Ray spawn_ray(const Vec3& position, const Vec3& normal, const Vec3& dir) {
    const double side = dir.dot(normal) >= 0.0 ? 1.0 : -1.0;
    return Ray{position + side * surface_epsilon(position) * normal, dir};
}

}  // namespace vpm
