#include "transport/single_scattering.h"

#include "core/henyey_greenstein.h"
#include "transport/direct_light.h"

namespace vpm {

bool bounces_find_lights(const Scene& scene) {
    if (!scene.area_lights().empty()) return true;
    for (const auto& light : scene.lights) {
        if (!light->at_infinity()) continue;
        Rng rng(0, 0);   // any direction the light samples: delta lights give pdf 0
        LightSample ls;
        if (light->sample_incident(Vec3::Zero(), rng, ls) && ls.pdf > 0.0) return true;
    }
    return false;
}

Rgb single_scattering_both_strategies(const Scene& scene, const Vec3& x, const Vec3& ray_dir, double g, Rng& rng,
                                      uint64_t& rays, const SegmentPoint* at) {
    Rgb sum = direct_light_in_medium(scene, x, ray_dir, g, rng, true, at);
    ++rays;
    // The bounce: phase / pdf = 1 for Henyey-Greenstein sampling.
    const double u1 = rng.uniform(), u2 = rng.uniform();
    const Vec3 wo = hg_sample(ray_dir, g, u1, u2);
    const Ray ray{x, wo};
    SurfaceHit hit;
    const bool on_surface = scene.intersect(ray, kInfinity, hit);
    const EmissionWeighting w = EmissionWeighting::after(true, x, hg_eval(ray_dir.dot(wo), g));
    const Rgb e = on_surface ? emitted_radiance(scene, ray, hit, w) : escaped_radiance(scene, wo, w);
    if ((e == 0.0).all()) return sum;
    ++rays;
    return sum + e * scene.transmittance(ray, on_surface ? hit.t : kInfinity, rng, on_surface ? hit.emitter : nullptr);
}

EmissionWeighting continued_emission(bool mis, const Vec3& x, const Vec3& ray_dir, const Vec3& wo, double g) {
    return EmissionWeighting::after(mis, x, mis ? hg_eval(ray_dir.dot(wo), g) : 0.0);
}

}  // namespace vpm
