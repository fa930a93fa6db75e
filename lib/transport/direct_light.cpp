#include "transport/direct_light.h"

#include "core/henyey_greenstein.h"
#include "transport/walk_steps.h"

namespace vpm {

Rgb direct_light_in_medium(const Scene& scene, const Vec3& x, const Vec3& ray_dir, double g, Rng& rng) {
    Rgb sum = Rgb::Zero();
    LightSample ls;
    for (const auto& light : scene.lights) {
        if (!light->sample_incident(x, rng, ls)) continue;
        // Light travels along -wi before scattering and along -ray_dir after it.
        const double phase = hg_eval((-ls.wi).dot(-ray_dir), g);
        if (phase == 0.0 || (ls.weight == 0.0).all()) continue;
        const double tr = scene.transmittance(Ray{x, ls.wi}, ls.distance, rng);
        sum += ls.weight * (phase * tr);
    }
    return sum;
}

Rgb direct_light_on_surface(const Scene& scene, const SurfaceHit& hit, Rng& rng) {
    Rgb sum = Rgb::Zero();
    if ((hit.reflectance == 0.0).all()) return sum;
    LightSample ls;
    for (const auto& light : scene.lights) {
        if (!light->sample_incident(hit.position, rng, ls)) continue;
        const double cos_theta = ls.wi.dot(hit.normal);   // normal faces the viewer
        if (cos_theta <= 0.0) continue;
        const Ray shadow = spawn_ray(hit.position, hit.normal, ls.wi);
        const double dist = ls.distance == kInfinity ? kInfinity : (ls.distance - (shadow.origin - hit.position).norm()) * (1.0 - 1e-7);
        const double tr = scene.transmittance(shadow, dist, rng);
        sum += ls.weight * (cos_theta * tr);
    }
    return sum * hit.reflectance * kInvPi;
}

}  // namespace vpm
