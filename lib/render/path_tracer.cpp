#include "render/path_tracer.h"

#include "core/henyey_greenstein.h"
#include "core/sampling.h"
#include "transport/direct_light.h"
#include "transport/walk_steps.h"

namespace vpm {

Rgb PathTracer::radiance(const Ray& camera_ray, Rng& rng) const {
    const int max_depth = walk_.max_depth;
    const int rr_depth = walk_.rr_depth;
    Ray ray = camera_ray;
    Rgb throughput = Rgb::Ones();
    Rgb radiance = Rgb::Zero();
    for (int depth = 0;; ++depth) {
        // `depth` scattering events so far; the vertex found now would be number depth + 1.
        const PathVertex v = next_vertex(scene_, ray, rng);
        if (v.escaped()) {
            if (depth == 0) radiance += throughput * scene_.escaped_radiance(ray.dir);
            break;
        }
        if (max_depth >= 0 && depth + 1 > max_depth) break;
        if (v.medium) {
            const Vec3 x = ray.at(v.medium.t);
            const Medium& m = *v.medium.medium;
            throughput *= m.albedo();   // collision estimator: scatter weight = albedo
            if ((throughput == 0.0).all()) break;
            radiance += throughput * direct_light_in_medium(scene_, x, ray.dir, m.g(), rng);
            const double u1 = rng.uniform(), u2 = rng.uniform();
            ray = Ray{x, hg_sample(ray.dir, m.g(), u1, u2)};
        } else {
            if ((v.hit.reflectance == 0.0).all()) break;
            radiance += throughput * direct_light_on_surface(scene_, v.hit, rng);
            throughput *= v.hit.reflectance;
            ray = diffuse_bounce(v.hit, rng);
        }
        if (!survive_roulette(throughput, depth + 1, rr_depth, rng)) break;
    }
    return radiance;
}

namespace {

struct PathTracerSettings : IntegratorSettings {
    WalkSettings walk;
    std::unique_ptr<Integrator> create(const Scene& scene) const override {
        return std::make_unique<PathTracer>(scene, walk);
    }
};

}  // namespace

std::unique_ptr<IntegratorSettings> read_path_tracer_settings(Params& render, Params&) {
    auto s = std::make_unique<PathTracerSettings>();
    s->walk = WalkSettings::read(render);
    return s;
}

}  // namespace vpm
