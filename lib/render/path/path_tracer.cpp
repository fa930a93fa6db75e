#include "render/path/path_tracer.h"

#include <optional>
#include <ostream>

#include "config/params.h"
#include "core/henyey_greenstein.h"
#include "core/sampling/sampling.h"
#include "transport/direct_light.h"
#include "transport/equiangular.h"
#include "transport/mis.h"
#include "transport/specular_step.h"
#include "transport/walk_steps.h"

namespace vpm {

Rgb PathTracer::radiance(const Ray& camera_ray, Rng& rng) const {
    const int max_depth = walk_.max_depth;
    const int rr_depth = walk_.rr_depth;
    const bool mis = walk_.mis;
    Ray ray = camera_ray;
    Rgb throughput = Rgb::Ones();
    Rgb radiance = Rgb::Zero();
    EmissionWeighting emission = EmissionWeighting::camera();   // how emission met next counts
    uint64_t rays = 0;   // shadow rays: the path tracer does not report them
    double radiance_scale = 1.0;   // the 1 / eta^2 factors of the refractions so far, for the roulette
    for (int depth = 0;; ++depth) {
        // `depth` scattering events so far; the vertex found now would be number depth + 1.
        const PathVertex v = next_vertex(scene_, ray, rng);
        const bool scatters = !(max_depth >= 0 && depth + 1 > max_depth);
        // Point and spot lights' single scattering along this segment, sampled equiangularly
        // (transport/equiangular.h); the collision's NEE to them below is weighted against it.
        std::optional<EquiangularSegment> segment;
        if (walk_.equiangular && scatters && scene_.has_media()) {
            segment.emplace(scene_, ray, v.on_surface ? v.hit.t : kInfinity);
            if (segment->empty())
                segment.reset();
            else
                radiance += throughput * segment->in_scattering(rng, rays, [](size_t, double s, double, double tau) {
                                return free_flight_density(s, tau);
                            });
        }
        if (v.escaped()) {
            radiance += throughput * escaped_radiance(scene_, ray.dir, emission);
            break;
        }
        // Emission belongs to the path of `depth` scattering events, like escaping does; the
        // light is black, so the path ends on it.
        if (!v.medium && v.hit.emitter) {
            radiance += throughput * emitted_radiance(scene_, ray, v.hit, emission);
            break;
        }
        if (!scatters) break;
        if (v.medium) {
            const Vec3 x = ray.at(v.medium.t);
            const Medium& m = *v.medium.medium;
            throughput *= m.albedo();   // collision estimator: scatter weight = albedo
            if ((throughput == 0.0).all()) break;
            if (segment) {
                const SegmentPoint at{&*segment, v.medium.t, segment->free_flight_density_at(v.medium.t, m.sigma_t(x))};
                radiance += throughput * direct_light_in_medium(scene_, x, ray.dir, m.g(), rng, mis, &at);
            } else {
                radiance += throughput * direct_light_in_medium(scene_, x, ray.dir, m.g(), rng, mis);
            }
            const double u1 = rng.uniform(), u2 = rng.uniform();
            const Vec3 wo = hg_sample(ray.dir, m.g(), u1, u2);
            emission = EmissionWeighting::after(mis, x, hg_eval(ray.dir.dot(wo), m.g()));
            ray = Ray{x, wo};
        } else {
            if (v.hit.specular) {   // a mirror or glass: the chain goes on, nothing is estimated here
                if (!camera_specular_step(v.hit, ray, throughput, emission, depth + 1, rr_depth, rng, &radiance_scale))
                    break;
                continue;
            }
            if ((v.hit.reflectance == 0.0).all()) break;
            radiance += throughput * direct_light_on_surface(scene_, v.hit, rng, mis);
            throughput *= v.hit.reflectance;
            ray = diffuse_bounce(v.hit, rng);
            emission = EmissionWeighting::after(mis, v.hit.position, std::max(0.0, ray.dir.dot(v.hit.normal)) * kInvPi);
        }
        if (!survive_roulette(throughput, depth + 1, rr_depth, rng, radiance_scale)) break;
    }
    return radiance;
}

void PathTracer::prepare(const PassContext& context, RunStats&) {
    if (sized_passes_ && context.first_of_run && context.log)
        *context.log << "path: render.time_limit: passes of 1 sample per pixel until the limit (render.spp = "
                     << context.configured_spp << " without render.passes is no pass size; set render.passes to pin "
                        "spp / passes)\n";
}

namespace {

struct PathTracerSettings : IntegratorSettings {
    WalkSettings walk;
    bool sized_passes = false;
    std::unique_ptr<Integrator> create(const Scene& scene) const override {
        return std::make_unique<PathTracer>(scene, walk, sized_passes);
    }
};

}  // namespace

std::unique_ptr<IntegratorSettings> read_path_tracer_settings(Params& render, Params&) {
    auto s = std::make_unique<PathTracerSettings>();
    s->walk = WalkSettings::read(render);
    // render.passes pins the pass (spp / passes samples); render.spp alone, which scene files carry
    // for runs without a limit, does not (as for the photon map's plan: docs/passes.md).
    s->sized_passes = render.has("time_limit") && render.real("time_limit", 0.0, Range::closed(0.0, 1e9)) > 0.0 &&
                      !render.has("passes");
    return s;
}

}  // namespace vpm
