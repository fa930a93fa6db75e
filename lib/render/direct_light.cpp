#include "render/direct_light.h"

#include "core/henyey_greenstein.h"

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
