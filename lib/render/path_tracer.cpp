#include "render/path_tracer.h"

#include "core/henyey_greenstein.h"
#include "core/sampling.h"
#include "render/direct_light.h"

namespace vpm {

Rgb PathTracer::radiance(const Ray& camera_ray, Rng& rng) const {
    const int max_depth = scene_.render.max_depth;
    const int rr_depth = scene_.render.rr_depth;
    Ray ray = camera_ray;
    Rgb throughput = Rgb::Ones();
    Rgb radiance = Rgb::Zero();
    for (int depth = 0;; ++depth) {
        // `depth` scattering events so far; the vertex found now would be number depth + 1.
        SurfaceHit hit;
        const bool hit_surface = scene_.intersect(ray, kInfinity, hit);
        const MediumEvent event = scene_.sample_medium(ray, hit_surface ? hit.t : kInfinity, rng);
        if (!event && !hit_surface) {
            if (depth == 0) radiance += throughput * scene_.escaped_radiance(ray.dir);
            break;
        }
        if (max_depth >= 0 && depth + 1 > max_depth) break;
        if (event) {
            const Vec3 x = ray.at(event.t);
            throughput *= event.medium->albedo();   // collision estimator: scatter weight = albedo
            if ((throughput == 0.0).all()) break;
            radiance += throughput * direct_light_in_medium(scene_, x, ray.dir, event.medium->g(), rng);
            const double u1 = rng.uniform(), u2 = rng.uniform();
            ray = Ray{x, hg_sample(ray.dir, event.medium->g(), u1, u2)};
        } else {
            if ((hit.reflectance == 0.0).all()) break;
            radiance += throughput * direct_light_on_surface(scene_, hit, rng);
            throughput *= hit.reflectance;
            const double u1 = rng.uniform(), u2 = rng.uniform();
            const Vec3 dir = Frame(hit.normal).to_world(sample_cosine_hemisphere(u1, u2)).normalized();
            ray = spawn_ray(hit.position, hit.normal, dir);
        }
        if (depth + 1 >= rr_depth) {
            const double q = std::min(0.95, throughput.maxCoeff());
            if (rng.uniform() >= q) break;
            throughput /= q;
        }
    }
    return radiance;
}

}  // namespace vpm
