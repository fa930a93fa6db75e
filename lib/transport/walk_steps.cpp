#include "transport/walk_steps.h"

namespace vpm {

namespace {
// Offset for rays leaving a surface. Positions are double and Embree sees float coordinates
// relative to the scene's centre (surfaces.cpp, which also skips self-hits by the refined double
// distance), so the offset must not grow with the distance from the origin: 1e-4 * |p| moved
// spawned rays 100 units at 1e6 (found by the translated cells of `vpm stress`). It must not be
// absolute either: a fixed 1e-4 put rays leaving the floor of a scene scaled by 1e-6 100 scene
// sizes away. The surfaces' own epsilon (1e-6 of their half extent) plus ~2^22 double
// ulps of |p| keeps the origin on the right side anywhere and scales with the scene.
double surface_epsilon(const SurfaceHit& hit) { return hit.epsilon + 1e-9 * hit.position.cwiseAbs().maxCoeff(); }
}  // namespace

Ray spawn_ray(const SurfaceHit& hit, const Vec3& dir) {
    const double side = dir.dot(hit.normal) >= 0.0 ? 1.0 : -1.0;
    return Ray{hit.position + side * surface_epsilon(hit) * hit.normal, dir};
}

}  // namespace vpm
