#include "transport/walk_steps.h"

#include <algorithm>

#include "scene/surfaces/offsets.h"

namespace vpm {

namespace {
// Offset for rays leaving a surface: the hit's own bound (scene/surfaces/offsets.h: its
// coordinates and shape, never the scene's extent, so a 1e6 shape elsewhere leaves a 1e-6 sphere
// intact), and at least the rounding of the position itself for hits made by hand.
double surface_epsilon(const SurfaceHit& hit) { return std::max(hit.epsilon, kSpawnOffset * magnitude(hit.position)); }
}  // namespace

Ray spawn_ray(const SurfaceHit& hit, const Vec3& dir) {
    const double side = dir.dot(hit.normal) >= 0.0 ? 1.0 : -1.0;
    return Ray{hit.position + side * surface_epsilon(hit) * hit.normal, dir};
}

}  // namespace vpm
