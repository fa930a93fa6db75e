#include "transport/mis.h"

namespace vpm {

Rgb emitted_radiance(const Scene& scene, const Ray& ray, const SurfaceHit& hit, const EmissionWeighting& w) {
    if (!hit.emitter || (hit.emitted == 0.0).all()) return Rgb::Zero();
    if (!hit.coincident_emitters) return hit.emitted * w.weight(*hit.emitter, ray.dir);
    // Several lights at this point (Scene::intersect): NEE sampled each with its own pdf.
    Rgb sum = Rgb::Zero();
    EmitterHit e;
    for (const Light* light : scene.area_lights())
        if (light->intersect(ray, hit.t * (1.0 + kCoincidentEmitters), e) && e.t >= hit.t * (1.0 - kCoincidentEmitters))
            sum += e.radiance * w.weight(*light, ray.dir);
    return sum;
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
