#include "transport/mis.h"

namespace vpm {

Rgb emitted_radiance(const SurfaceHit& hit, const Vec3& dir, const EmissionWeighting& w) {
    if (!hit.emitter || (hit.emitted == 0.0).all()) return Rgb::Zero();
    return hit.emitted * w.weight(*hit.emitter, dir);
}

Rgb escaped_radiance(const Scene& scene, const Vec3& dir, const EmissionWeighting& w) {
    Rgb sum = Rgb::Zero();
    for (const auto& light : scene.lights) {
        const Rgb l = light->escaped_radiance(dir);
        if ((l == 0.0).all()) continue;
        sum += l * w.weight(*light, dir);
    }
    return sum;
}

}  // namespace vpm
