#include "render/photon_map_integrator.h"

#include <array>

#include <tbb/enumerable_thread_specific.h>

#include "core/henyey_greenstein.h"
#include "core/sampling.h"
#include "photon/ball_extinction.h"
#include "photon/bounded_radius.h"
#include "render/direct_light.h"
#include "render/path_vertex.h"

namespace vpm {

namespace {

double total_sigma_t(const Scene& scene, const Vec3& x) {
    double sigma_t = 0.0;   // overlapping media: photons of all of them are in the map
    for (const auto& m : scene.media) sigma_t += m->sigma_t(x);
    return sigma_t;
}

}  // namespace

struct PhotonMapIntegrator::ThreadState {
    explicit ThreadState(const Scene& scene) : ball(scene.media) {}
    BallExtinction ball;   // mean sigma_t over kNN balls (photons.extinction = "ball")
    struct Local {
        GatherBuffers buffers;
        EstimatorStats stats, surface_stats;
        uint64_t continued = 0;   // camera paths continued past a collision (bounded radius)
    };
    mutable tbb::enumerable_thread_specific<Local> local;
};

PhotonMapIntegrator::PhotonMapIntegrator(const Scene& scene, const PhotonMap& map, const PhotonMap* surface_map)
    : scene_(scene), map_(map), surface_map_(surface_map), estimator_(parse_estimator(scene.photons.estimator)), k_(size_t(scene.photons.k)),
      max_radius_(scene.photons.max_radius > 0 ? scene.photons.max_radius : kInfinity),
      nee_(scene.photons.direct == "nee"), ball_extinction_(scene.photons.extinction == "ball"),
      threads_(std::make_unique<ThreadState>(scene)) {}

PhotonMapIntegrator::~PhotonMapIntegrator() = default;

EstimatorStats PhotonMapIntegrator::stats() const {
    EstimatorStats total;
    for (const auto& l : threads_->local) total.merge(l.stats);
    return total;
}

uint64_t PhotonMapIntegrator::continued_paths() const {
    uint64_t total = 0;
    for (const auto& l : threads_->local) total += l.continued;
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
            const double sigma_t = total_sigma_t(scene_, x);
            if (sigma_t > 0.0 && !map_.empty()) {
                auto& local = threads_->local.local();
                const double radius = bounded_radius(max_radius_, scene_.photons.max_radius_mfp, sigma_t);
                const Estimate<Rgb> s = estimate_in_scattering(map_, x, -ray.dir, m.g(), estimator_, k_, radius,
                                                               local.buffers, &local.stats);
                if (radius < max_radius_) {   // the mean-free-path bound (photon/bounded_radius.h)
                    const BoundedQuery q = bounded_query(s, k_);
                    if (q == BoundedQuery::zero) break;
                    if (q == BoundedQuery::continue_path) {   // too few photons: scatter and go on
                        ++local.continued;
                        if (!nee_) radiance += weight * direct_light_in_medium(scene_, x, ray.dir, m.g(), rng);
                        throughput = weight;
                        const double u1 = rng.uniform(), u2 = rng.uniform();
                        ray = Ray{x, hg_sample(ray.dir, m.g(), u1, u2)};
                        if (!survive_roulette(throughput, depth + 1, scene_.render.rr_depth, rng)) break;
                        continue;
                    }
                }
                // The ball can miss every quadrature point's smoke only if it is tiny; then use the point.
                const double ball = ball_extinction_ && s.radius > 0.0 ? threads_->ball.mean(x, s.radius) : 0.0;
                radiance += weight * s.value / (ball > 0.0 ? ball : sigma_t);
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
