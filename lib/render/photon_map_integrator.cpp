#include "render/photon_map_integrator.h"

#include <array>
#include <ostream>

#include <tbb/enumerable_thread_specific.h>

#include "core/henyey_greenstein.h"
#include "core/sampling.h"
#include "photon/ball_extinction.h"
#include "photon/bounded_radius.h"
#include "scene/params.h"
#include "transport/direct_light.h"
#include "transport/mis.h"
#include "transport/walk_steps.h"

namespace vpm {

namespace {

double total_sigma_t(const Scene& scene, const Vec3& x) {
    double sigma_t = 0.0;   // overlapping media: photons of all of them are in the map
    for (const auto& m : scene.media) sigma_t += m->sigma_t(x);
    return sigma_t;
}

Bounds3 media_bounds(const Scene& scene) {
    Bounds3 b;
    for (const auto& m : scene.media) b.extend(m->bounds());
    return b;
}

}  // namespace

struct PhotonMapIntegrator::ThreadState {
    explicit ThreadState(const Scene& scene) : ball(scene.media) {}
    BallExtinction ball;   // mean sigma_t over kNN balls (photons.extinction = "ball")
    struct Local {
        GatherBuffers buffers;
        EstimatorStats stats, surface_stats;
        uint64_t continued = 0;   // camera paths continued past a collision (bounded radius)
        uint64_t march_wide = 0;  // march queries whose kNN ball exceeds max_radius_mfp mean free paths
    };
    mutable tbb::enumerable_thread_specific<Local> local;
};

PhotonMapIntegrator::PhotonMapIntegrator(const Scene& scene, const PhotonMapSettings& settings)
    : scene_(scene), settings_(settings), owns_maps_(true), map_(&owned_.volume), surface_map_(nullptr),
      max_radius_(settings.search_radius()), k_(size_t(settings.k)), media_bounds_(media_bounds(scene)), threads_(std::make_unique<ThreadState>(scene)) {}

PhotonMapIntegrator::PhotonMapIntegrator(const Scene& scene, const PhotonMapSettings& settings,
                                         const PhotonMap& volume_map, const PhotonMap* surface_map)
    : scene_(scene), settings_(settings), owns_maps_(false), map_(&volume_map), surface_map_(surface_map),
      max_radius_(settings.search_radius()), k_(size_t(settings.k)), media_bounds_(media_bounds(scene)), threads_(std::make_unique<ThreadState>(scene)) {}

PhotonMapIntegrator::~PhotonMapIntegrator() = default;

void PhotonMapIntegrator::prepare(const PassContext& context, RunStats& stats) {
    k_ = size_t(settings_.k_for_pass(context.pass));
    if (!owns_maps_) return;
    std::ostream* log = context.first_of_run ? context.log : nullptr;
    const bool surface = scene_.uses_embree() && !settings_.final_gather;
    if (scene_.has_media() || surface) {
        owned_ = PhotonMaps();   // one map in memory at a time: free the last pass's first
        owned_ = run_photon_pass(scene_, settings_, context, surface, stats, allocation_);
        surface_map_ = surface ? &owned_.surface : nullptr;
    } else if (log) {
        *log << "photons: no media and no surface map, so no photon pass\n";
    }
    if (!scene_.has_media() && log) *log << "photons: no media, so the volume photon map is empty\n";
    if (scene_.uses_embree() && !surface && log)
        *log << "photons: final_gather = true, so no surface photon map (paths continue through surfaces)\n";
}

void PhotonMapIntegrator::collect(RunStats& stats, std::ostream* log) const {
    stats.volume_estimates = this->stats();
    stats.continued_paths = continued_paths();
    if (log)
        *log << "estimates: " << stats.volume_estimates->to_string() << "; camera paths continued past a collision "
             << "(fewer than k photons within photons.max_radius_mfp): " << *stats.continued_paths << "\n";
    uint64_t wide = 0;
    for (const auto& l : threads_->local) wide += l.march_wide;
    if (settings_.gather == GatherMode::march) {
        stats.march_wide_queries = wide;
        if (wide > 0 && log)
            *log << "warning: photons.gather = \"march\": " << wide << " of " << stats.volume_estimates->queries
                 << " queries used a kNN ball wider than photons.max_radius_mfp = " << settings_.max_radius_mfp
                 << " mean free paths; in dense media the march is biased low there (the collision gather is not)\n";
    }
    const EstimatorStats ss = surface_stats();
    if (ss.queries) {
        stats.surface_estimates = ss;
        if (log) *log << "surface estimates: " << ss.to_string() << "\n";
    }
}

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
    const int max_depth = settings_.walk.max_depth;
    Ray ray = camera_ray;
    Rgb throughput = Rgb::Ones();
    Rgb radiance = Rgb::Zero();
    EmissionWeighting emission = EmissionWeighting::camera();   // transport/mis.h
    for (int depth = 0;; ++depth) {
        const PathVertex v = next_vertex(scene_, ray, rng);
        const MediumEvent& event = v.medium;
        const SurfaceHit& hit = v.hit;
        if (v.escaped()) {
            radiance += throughput * escaped_radiance(scene_, ray.dir, emission);
            if (settings_.gather == GatherMode::march && !(max_depth >= 0 && depth + 1 > max_depth))
                radiance += throughput * march_in_scattering(ray, kInfinity, rng);
            break;
        }
        if (!event && hit.emitter) radiance += throughput * emitted_radiance(hit, ray.dir, emission);   // black: ends below
        if (max_depth >= 0 && depth + 1 > max_depth) break;
        if (settings_.gather == GatherMode::march) {
            // The medium's in-scattering along this segment comes from the march; the collision
            // sampled above only decides whether the path reaches the surface behind (probability T).
            radiance += throughput * march_in_scattering(ray, v.on_surface ? hit.t : kInfinity, rng);
            if (event) break;
        }
        if (event) {
            const Vec3 x = ray.at(event.t);
            const Medium& m = *event.medium;
            const Rgb weight = throughput * m.albedo();
            if ((weight == 0.0).all()) break;
            if (settings_.direct == DirectLighting::nee) radiance += weight * direct_light_in_medium(scene_, x, ray.dir, m.g(), rng);
            const double sigma_t = total_sigma_t(scene_, x);
            if (sigma_t > 0.0 && !map_->empty()) {
                auto& local = threads_->local.local();
                const double radius = bounded_radius(max_radius_, settings_.max_radius_mfp, sigma_t);
                const bool bounded = radius < max_radius_;   // the mean-free-path bound (photon/bounded_radius.h)
                // k above the stored count + 1: no ball can hold k - 1 photons, so no query is needed.
                const bool too_few = bounded && k_ >= map_->size() + 2;
                Estimate<Rgb> s;
                if (!too_few)
                    s = estimate_in_scattering(*map_, x, -ray.dir, m.g(), settings_.estimator, k_, radius,
                                               local.buffers, &local.stats);
                if (bounded) {
                    const BoundedQuery q = too_few ? BoundedQuery::continue_path : bounded_query(s, k_);
                    if (q == BoundedQuery::zero) break;
                    if (q == BoundedQuery::continue_path) {   // too few photons: scatter and go on
                        ++local.continued;
                        if (settings_.direct != DirectLighting::nee)
                            radiance += weight * direct_light_in_medium(scene_, x, ray.dir, m.g(), rng);
                        throughput = weight;
                        const double u1 = rng.uniform(), u2 = rng.uniform();
                        ray = Ray{x, hg_sample(ray.dir, m.g(), u1, u2)};
                        emission = EmissionWeighting::after(false, x, 0.0);   // its NEE above weighed 1
                        if (!survive_roulette(throughput, depth + 1, settings_.walk.rr_depth, rng)) break;
                        continue;
                    }
                }
                // The ball can miss every quadrature point's smoke only if it is tiny; then use the point.
                const double ball = settings_.extinction == ExtinctionNormalisation::ball && s.radius > 0.0 ? threads_->ball.mean(x, s.radius) : 0.0;
                radiance += weight * s.value / (ball > 0.0 ? ball : sigma_t);
            }
            break;
        }
        if ((hit.reflectance == 0.0).all()) break;
        if (surface_map_) {   // the surface photon map gives the light the path would gather
            if (settings_.direct == DirectLighting::nee) radiance += throughput * direct_light_on_surface(scene_, hit, rng);
            if (!surface_map_->empty()) {
                auto& local = threads_->local.local();
                const Estimate<Rgb> e = estimate_surface_irradiance(*surface_map_, hit.position, hit.normal,
                                                                    settings_.estimator, k_, max_radius_, local.buffers, &local.surface_stats);
                radiance += throughput * hit.reflectance * (e.value / kPi);
            }
            break;
        }
        radiance += throughput * direct_light_on_surface(scene_, hit, rng, settings_.walk.mis);
        throughput *= hit.reflectance;
        ray = diffuse_bounce(hit, rng);
        emission = EmissionWeighting::after(settings_.walk.mis, hit.position, std::max(0.0, ray.dir.dot(hit.normal)) * kInvPi);
        if (!survive_roulette(throughput, depth + 1, settings_.walk.rr_depth, rng)) break;
    }
    return radiance;
}

Rgb PhotonMapIntegrator::march_in_scattering(const Ray& ray, double t_end, Rng& rng) const {
    double t0, t1;
    if (!media_bounds_.intersect(ray, t_end, t0, t1) || !(t1 > t0) || !std::isfinite(t1 - t0)) return Rgb::Zero();
    const int n = settings_.gather_queries;
    const double dt = (t1 - t0) / n;
    const bool nee = settings_.direct == DirectLighting::nee;
    Rgb sum = Rgb::Zero();
    double transmittance = 1.0, t_prev = 0.0;
    for (int j = 0; j < n; ++j) {
        const double t = t0 + (j + rng.uniform()) * dt;   // stratified, jittered
        // T(0, t) as a product of independent ratio-tracking estimates over consecutive pieces.
        for (const auto& m : scene_.media) transmittance *= m->transmittance(Ray{ray.at(t_prev), ray.dir}, t - t_prev, rng);
        t_prev = t;
        if (transmittance == 0.0) break;
        const Vec3 x = ray.at(t);
        double sigma_t = 0.0, dominant = 0.0, g = 0.0;
        Rgb sigma_s = Rgb::Zero();
        for (const auto& m : scene_.media) {
            const double st = m->sigma_t(x);
            sigma_t += st;
            sigma_s += m->albedo() * st;
            if (st > dominant) {
                dominant = st;
                g = m->g();
            }
        }
        if (!(sigma_t > 0.0) || (sigma_s == 0.0).all()) continue;
        Rgb in = Rgb::Zero();   // phase-weighted incident radiance at x
        if (nee) in += direct_light_in_medium(scene_, x, ray.dir, g, rng);
        if (!map_->empty()) {
            auto& local = threads_->local.local();
            const Estimate<Rgb> s = estimate_in_scattering(*map_, x, -ray.dir, g, settings_.estimator, k_,
                                                           max_radius_, local.buffers, &local.stats);
            const double ball = settings_.extinction == ExtinctionNormalisation::ball && s.radius > 0.0
                                    ? threads_->ball.mean(x, s.radius)
                                    : 0.0;
            in += s.value / (ball > 0.0 ? ball : sigma_t);   // S estimates sigma_t times the incident radiance
            // The march has no path to continue where the ball spans many mean free paths (the
            // collision gather's bound, photon/bounded_radius.h): count those queries, they are biased low.
            if (settings_.max_radius_mfp > 0.0 && s.radius * sigma_t > settings_.max_radius_mfp) ++local.march_wide;
        }
        sum += (transmittance * dt) * sigma_s * in;
    }
    return sum;
}

namespace {

struct PhotonMapIntegratorSettings : IntegratorSettings {
    PhotonMapSettings settings;
    std::unique_ptr<Integrator> create(const Scene& scene) const override {
        return std::make_unique<PhotonMapIntegrator>(scene, settings);
    }
};

}  // namespace

std::unique_ptr<IntegratorSettings> read_photon_map_settings(Params& render, Params& root) {
    auto s = std::make_unique<PhotonMapIntegratorSettings>();
    Params photons = root.table("photons");
    s->settings = PhotonMapSettings::read(render, photons);
    photons.finish();
    return s;
}

const PhotonMapSettings& photon_map_settings(const RunConfig& config) {
    return static_cast<const PhotonMapIntegratorSettings&>(config.settings_for("photon_map")).settings;
}

}  // namespace vpm
