#include "transport/direct_light.h"

#include "core/henyey_greenstein.h"
#include "transport/mis.h"
#include "transport/walk_steps.h"

namespace vpm {

Rgb direct_light_in_medium(const Scene& scene, const Vec3& x, const Vec3& ray_dir, double g, Rng& rng, bool mis,
                           const SegmentPoint* at) {
    Rgb sum = Rgb::Zero();
    for (size_t i = 0; i < scene.lights.size(); ++i) {
        const auto& light = scene.lights[i];
        LightSample ls;   // fresh: a light that leaves pdf unset is a delta light
        if (!light->sample_incident(x, rng, ls)) continue;
        // Light travels along -wi before scattering and along -ray_dir after it. The phase value
        // is also the pdf with which the walk samples wi (hg_sample).
        const double phase = hg_eval((-ls.wi).dot(-ray_dir), g);
        if (phase == 0.0 || (ls.weight == 0.0).all()) continue;
        const double tr = scene.transmittance(Ray{x, ls.wi}, ls.distance, rng, light.get());
        if (at)
            sum += ls.weight * (phase * tr * light_sample_weight(mis, ls.pdf, phase) * at->weight(i));
        else
            sum += ls.weight * (phase * tr * light_sample_weight(mis, ls.pdf, phase));
    }
    return sum;
}

Rgb direct_light_on_surface(const Scene& scene, const SurfaceHit& hit, Rng& rng, bool mis) {
    Rgb sum = Rgb::Zero();
    if ((hit.reflectance == 0.0).all()) return sum;
    for (const auto& light : scene.lights) {
        LightSample ls;
        if (!light->sample_incident(hit.position, rng, ls)) continue;
        const double cos_theta = ls.wi.dot(hit.normal);   // normal faces the viewer
        if (cos_theta <= 0.0) continue;
        const Ray shadow = spawn_ray(hit, ls.wi);
        const double dist = ls.distance == kInfinity ? kInfinity : (ls.distance - (shadow.origin - hit.position).norm()) * (1.0 - 1e-7);
        const double tr = scene.transmittance(shadow, dist, rng, light.get());
        // The walk's cosine-weighted bounce takes wi with pdf cos / pi.
        sum += ls.weight * (cos_theta * tr * light_sample_weight(mis, ls.pdf, cos_theta * kInvPi));
    }
    return sum * hit.reflectance * kInvPi;
}

}  // namespace vpm
