#include "render/photon_map_integrator.h"

#include <tbb/enumerable_thread_specific.h>

#include "core/sampling.h"
#include "render/direct_light.h"
#include "render/path_vertex.h"

namespace vpm {

struct PhotonMapIntegrator::ThreadState {
    struct Local {
        GatherBuffers buffers;
        EstimatorStats stats, surface_stats;
    };
    mutable tbb::enumerable_thread_specific<Local> local;
};

PhotonMapIntegrator::PhotonMapIntegrator(const Scene& scene, const PhotonMap& map, const PhotonMap* surface_map)
    : scene_(scene), map_(map), surface_map_(surface_map), estimator_(parse_estimator(scene.photons.estimator)), k_(size_t(scene.photons.k)),
      max_radius_(scene.photons.max_radius > 0 ? scene.photons.max_radius : kInfinity),
      nee_(scene.photons.direct == "nee"), threads_(std::make_unique<ThreadState>()) {}

PhotonMapIntegrator::~PhotonMapIntegrator() = default;

EstimatorStats PhotonMapIntegrator::stats() const {
    EstimatorStats total;
    for (const auto& l : threads_->local) total.merge(l.stats);
    return total;
}

EstimatorStats PhotonMapIntegrator::surface_stats() const {
    EstimatorStats total;
    for (const auto& l : threads_->local) total.merge(l.surface_stats);
    return total;
}

Rgb PhotonMapIntegrator::radiance(const Ray& camera_ray, Rng& rng) const {
    const int max_depth = scene_.render.max_depth;
    Ray ray = camera_ray;
    Rgb throughput = Rgb::Ones();
    Rgb radiance = Rgb::Zero();
    for (int depth = 0;; ++depth) {
        const PathVertex v = next_vertex(scene_, ray, rng);
        const MediumEvent& event = v.medium;
        const SurfaceHit& hit = v.hit;
        if (v.escaped()) {
            if (depth == 0) radiance += throughput * scene_.escaped_radiance(ray.dir);
            break;
        }
        if (max_depth >= 0 && depth + 1 > max_depth) break;
        if (event) {
            const Vec3 x = ray.at(event.t);
            const Medium& m = *event.medium;
            const Rgb weight = throughput * m.albedo();
            if ((weight == 0.0).all()) break;
            if (nee_) radiance += weight * direct_light_in_medium(scene_, x, ray.dir, m.g(), rng);
            double sigma_t = 0.0;   // overlapping media: photons of all of them are in the map
            for (const auto& other : scene_.media) sigma_t += other->sigma_t(x);
            if (sigma_t > 0.0 && !map_.empty()) {
                auto& local = threads_->local.local();
                const Estimate<Rgb> s = estimate_in_scattering(map_, x, -ray.dir, m.g(), estimator_, k_, max_radius_,
                                                               local.buffers, &local.stats);
                radiance += weight * s.value / sigma_t;
            }
            break;
        }
        if ((hit.reflectance == 0.0).all()) break;
        if (surface_map_) {   // the surface photon map gives the light the path would gather
            if (nee_) radiance += throughput * direct_light_on_surface(scene_, hit, rng);
            if (!surface_map_->empty()) {
                auto& local = threads_->local.local();
                const Estimate<Rgb> e = estimate_surface_irradiance(*surface_map_, hit.position, hit.normal, estimator_,
                                                                    k_, max_radius_, local.buffers, &local.surface_stats);
                radiance += throughput * hit.reflectance * (e.value / kPi);
            }
            break;
        }
        radiance += throughput * direct_light_on_surface(scene_, hit, rng);
        throughput *= hit.reflectance;
        ray = diffuse_bounce(hit, rng);
        if (!survive_roulette(throughput, depth + 1, scene_.render.rr_depth, rng)) break;
    }
    return radiance;
}

}  // namespace vpm
