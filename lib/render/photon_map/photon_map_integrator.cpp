#include "render/photon_map/photon_map_integrator.h"

#include <algorithm>
#include <array>
#include <optional>
#include <ostream>
#include <sstream>

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "core/henyey_greenstein.h"
#include "core/progress.h"
#include "core/sampling.h"
#include "photon/estimate/ball_extinction.h"
#include "photon/estimate/bounded_radius.h"
#include "render/photon_map/gathers/segment_gather.h"
#include "render/plan/pass_plan.h"
#include "render/plan/work_units.h"
#include "transport/seen_through.h"
#include "transport/segment_direct_light.h"
#include "transport/single_scattering.h"
#include "transport/specular_step.h"
#include "scene/media/homogeneous_medium.h"
#include "config/params.h"
#include "transport/direct_light.h"
#include "transport/equiangular.h"
#include "transport/march_points.h"
#include "transport/mis.h"
#include "transport/walk_steps.h"

namespace vpm {

namespace {

// The gather in force before any pilot has run: the chosen one, and for "auto" or "pilot" the
// per-segment threshold.
GatherMode initial_gather(GatherMode mode) { return gather_entry(mode).chooses ? GatherMode::threshold : mode; }

}  // namespace

struct PhotonMapIntegrator::ThreadState {
    explicit ThreadState(const Scene& scene) : ball(scene.media) {}
    BallExtinction ball;   // mean sigma_t over kNN balls (photons.extinction = "ball", "linear")
    mutable CounterSet local;
};

PhotonMapIntegrator::PhotonMapIntegrator(const Scene& scene, const PhotonMapSettings& settings)
    : scene_(scene), settings_(settings), owns_maps_(true), map_(&owned_.volume), surface_map_(nullptr),
      max_radius_(settings.search_radius()), k_(size_t(settings.k)), volume_estimator_(settings.estimator),
      surface_estimator_(settings.estimator), threads_(std::make_unique<ThreadState>(scene)),
      continuation_(scene, settings.walk) {
    gather_ = initial_gather(settings.gather);
    both_strategies_ = settings.walk.mis && bounces_find_lights(scene);
}

PhotonMapIntegrator::PhotonMapIntegrator(const Scene& scene, const PhotonMapSettings& settings,
                                         const PhotonMap& volume_map, const PhotonMap* surface_map)
    : scene_(scene), settings_(settings), owns_maps_(false), map_(&volume_map), surface_map_(surface_map),
      max_radius_(settings.search_radius()), k_(size_t(settings.k)), volume_estimator_(settings.estimator),
      surface_estimator_(settings.estimator), threads_(std::make_unique<ThreadState>(scene)),
      continuation_(scene, settings.walk) {
    gather_ = initial_gather(settings.gather);
    both_strategies_ = settings.walk.mis && bounces_find_lights(scene);
    schedule_pass(0);
    if (gather_entry(gather_).build) build_segment_gather(nullptr, nullptr);
}

PhotonMapIntegrator::~PhotonMapIntegrator() = default;

void PhotonMapIntegrator::schedule_pass(int pass) {
    const PassRadii r = settings_.radii_for_pass(pass, scene_.has_media(), surface_map_ != nullptr || traces_surface_map());
    k_ = size_t(r.k);
    volume_estimator_ = settings_.estimator.with_radius_scale(r.volume_scale);
    surface_estimator_ = settings_.estimator.with_radius_scale(r.surface_scale);
    beam_scale_ = r.beam_scale;
}

void PhotonMapIntegrator::prepare(const PassContext& context, RunStats& stats) {
    schedule_pass(context.pass);
    if (radii_log_.radii.size() < RunStats::kPassRecords) {
        radii_log_.pass.push_back(context.pass);
        radii_log_.radii.push_back(settings_.radii_for_pass(context.pass, scene_.has_media(), surface_map_ != nullptr || traces_surface_map()));
    }
    radii_log_.last_pass = context.pass;
    // A run starting at a later pass plans on pass 0's map first: a plan without the map then saves this pass's.
    if (owns_maps_ && settings_.plans() && !plan_ && context.pass != 0) plan_auto(context, stats);
    if (!owns_maps_) {
        if (settings_.gather == GatherMode::pilot) choose_gather(context);
        if (settings_.plans() && !plan_) plan_auto(context, stats);
        return;
    }
    std::ostream* log = context.first_of_run ? context.log : nullptr;
    const bool surface = traces_surface_map();
    if (no_map_) {   // render/plan/no_map_candidate.h: the plan found the map not worth its pass
        owned_ = PhotonMaps();
        surface_map_ = nullptr;
    } else if (scene_.has_media() || surface) {
        // Pass 0 of an auto plan is first traced at photons.count: the pilot's map, which the plan is made on.
        trace_maps(context, plan_ ? plan_->count : first_map_photons(context, stats), surface, stats);
        if (!decision_map_ && wants_decision_map()) trace_decision_map(context, stats);
        // k above the stored count: say so once per run (the maps are then not queried).
        const bool volume_short = scene_.has_media() && !gather_entry(settings_.gather).stores_beams && volume_map_starved();
        const bool surface_short = surface_map_ && surface_map_->size() < k_;
        if ((volume_short || surface_short) && !warned_k_ && context.log) {
            warned_k_ = true;
            *context.log << "warning: photons.k = " << k_ << " exceeds the " << (volume_short ? map_->size() : surface_map_->size())
                         << (volume_short ? " volume" : " surface") << " photons stored in pass " << context.pass
                         << ": no estimate can use k photons, so camera paths are path traced past every "
                         << (volume_short ? "medium collision" : "surface hit") << " instead (lower photons.k or raise photons.count)\n";
        }
        if (gather_entry(settings_.gather).build) build_segment_gather(log, &stats);
    } else if (log) {
        *log << "photons: no media and no surface map, so no photon pass\n";
    }
    if (!scene_.has_media() && log) *log << "photons: no media, so the volume photon map is empty\n";
    if (settings_.gather == GatherMode::pilot) choose_gather(context);
    if (settings_.plans() && !plan_) {
        plan_auto(context, stats);
        // Rendered with the pilot's small map, pass 0 would keep that map's bias and noise in the
        // image (all of it where the time limit allows one pass): it is traced again at the plan's
        // size, as every later pass is, and as a run starting at a later pass renders it.
        if (!no_map_ && plan_->count > first_map_photons_ && (scene_.has_media() || surface)) {
            if (log)
                *log << "photons: pass 0 traced again with the plan's " << plan_->count << " photons (the pilot's "
                     << first_map_photons_ << " only chose the plan)\n";
            one_off_seconds_ += last_trace_seconds_;   // the pilot's map
            ledger_.pass_maps -= uint64_t(first_map_photons_);   // it served the pilot alone
            ledger_.pilot_only += uint64_t(first_map_photons_);
            ledger_.passes_traced -= 1;
            trace_maps(context, plan_->count, surface, stats);
        }
    }
    if (scene_.uses_embree() && !surface && log)
        *log << "photons: final_gather = true, so no surface photon map (paths continue through surfaces)\n";
}

int64_t PhotonMapIntegrator::first_map_photons(const PassContext& context, RunStats& stats) {
    if (first_map_photons_ > 0) return first_map_photons_;
    first_map_photons_ = settings_.count;
    if (owns_maps_ && settings_.size_photons && scene_.has_media()) {
        const Timer probe_timer;
        const PilotPhotonCount p = pilot_photon_count(scene_, settings_, context, traces_surface_map(), allocation_);
        one_off_seconds_ += probe_timer.seconds();
        first_map_photons_ = p.count;
        ledger_.probe += uint64_t(p.probe_photons);
        if (context.log && context.first_of_run && p.count < settings_.count)
            *context.log << "photons: the pilot's map of " << p.count << " photons, not photons.count = " << settings_.count
                         << ": a probe of " << p.probe_photons << " stored " << p.stored_per_photon << " per photon, and "
                         << kPilotStoredPhotons << " stored are what the pilot needs (render/photon_map/photon_pass.h)\n";
    }
    if (owns_maps_ && settings_.sizes_beam_pass() && scene_.has_media()) {
        if (!beam_pass_) plan_beam_pass(context, stats);
        first_map_photons_ = beam_pass_->count;
        return first_map_photons_;   // the pilots' counted work also judged a pinned count
    }
    if (owns_maps_ && !settings_.size_photons && settings_.time_limit > 0.0 && scene_.has_media())
        check_pinned_count_fits(context, stats);
    return first_map_photons_;
}

// photons.count pinned under render.time_limit: the pass is traced at that count whatever the
// limit, so a probe's counted work (render/plan/work_units.h: deterministic, no clock) says before
// the trace whether its photon pass alone fits, and a warning (log and sidecar) names the count that would.
void PhotonMapIntegrator::check_pinned_count_fits(const PassContext& context, RunStats& stats) {
    const Timer probe_timer;
    const PilotPhotonCount p = pilot_photon_count(scene_, settings_, context, traces_surface_map(), allocation_);
    one_off_seconds_ += probe_timer.seconds();
    ledger_.probe += uint64_t(p.probe_photons);
    const WorkUnits w = work_units(scene_, k_);
    double per_photon = w.path + w.collision * p.collisions_per_photon + w.stored * p.stored_per_photon;
    // The point-beam gather then finds every stored photon's radius: a kNN query each.
    if (settings_.gather == GatherMode::point_beam)
        per_photon += p.stored_per_photon * query_price(w, std::max(1.0, p.stored_per_photon * double(settings_.count)));
    const double budget = settings_.time_limit * kWorkUnitsPerSecond, work = per_photon * double(settings_.count);
    if (!(work > budget)) return;
    std::ostringstream s;
    s.precision(3);
    s << "render.time_limit = " << settings_.time_limit << " s: photons.count = " << settings_.count
      << (settings_.count_given ? " is set" : " (its default)") << ", and its photon pass alone counts " << work / kWorkUnitsPerSecond << " s of one core (a probe of "
      << p.probe_photons << " photons: " << p.collisions_per_photon << " collisions and " << p.stored_per_photon
      << " stored per photon), so the first pass overruns the limit; ";
    if (const double fit = std::floor(budget / per_photon); fit >= 1.0) s << "about " << fit << " photons fit";
    else s << "not one photon fits";
    // A count the plan could have sized was set by the user; for the other gathers it may be the default.
    if (settings_.plan_sizes_passes()) s << ", or leave photons.count unset for the plan to size it";
    else s << " (the plan sizes photons only for the \"collision\" and \"march\" gathers: set photons.count to fit)";
    stats.warn(s.str(), context.log);
}

void PhotonMapIntegrator::trace_maps(const PassContext& context, int64_t count, bool surface, RunStats& stats) {
    retire_segment_gather(stats);   // its structure points into the last pass's map
    owned_ = PhotonMaps();   // one map in memory at a time: free the last pass's first
    PhotonMapSettings pass_settings = settings_;
    pass_settings.count = count;
    const Timer timer;
    owned_ = run_photon_pass(scene_, pass_settings, context, surface, stats, allocation_);
    last_trace_seconds_ = timer.seconds();
    ledger_.pass_maps += uint64_t(count);
    ledger_.passes_traced += 1;
    surface_map_ = surface ? &owned_.surface : nullptr;
    use_regions(owned_.volume_regions.empty() ? nullptr : &owned_.volume_regions,
                owned_.surface_regions.empty() ? nullptr : &owned_.surface_regions);
    set_map_emitted(double(count));
}

void PhotonMapIntegrator::use_regions(const RegionPhotonMaps* volume, const RegionPhotonMaps* surface) {
    volume_regions_ = volume;
    surface_regions_ = surface;
}

bool PhotonMapIntegrator::traces_surface_map() const {
    return scene_.uses_embree() && !settings_.final_gather;
}

bool PhotonMapIntegrator::wants_decision_map() const {
    return scene_.has_media() && settings_.max_radius_mfp > 0.0 && gather_entry(settings_.gather).uses_decision_map;
}

void PhotonMapIntegrator::trace_decision_map(const PassContext& context, RunStats& stats) {
    // Its own seed, and the run's streams rather than the pass's: independent of every pass's map, and
    // the same map on every machine rendering passes of the run (vpm merge).
    PassContext c = context;
    c.seed = mix64(context.seed ^ 0x646563697369ULL);
    c.stream_offset = context.run_stream_offset;
    c.first_of_run = false;
    c.log = nullptr;
    RunStats traced;   // its counts are not the run's photon passes'
    PhotonMapSettings decision_settings = settings_;
    // An eighth of photons.count, also where the auto plan's pilot map is smaller (render/photon_map/photon_pass.h):
    // the passes that keep the map have photons.count or more, and the decision's ball and count are
    // scaled for that ratio (docs/integrators.md: the decision map).
    decision_settings.count = std::max<int64_t>(1, settings_.count / kDecisionMapShare);
    // The run's photons per light (traced after its first map, which set them).
    decision_owned_ = std::move(run_photon_pass(scene_, decision_settings, c, false, traced, allocation_).volume);
    decision_map_ = &decision_owned_;
    decision_cells_ = PhotonCellCounts(decision_owned_);
    decision_emitted_ = double(decision_settings.count);
    ledger_.decision_map += uint64_t(decision_settings.count);
    set_map_emitted(map_emitted_);
    double seconds = 0.0;
    for (const PhaseStats& phase : traced.phases) seconds += phase.seconds;
    stats.phase("decision_map", seconds);
    one_off_seconds_ += seconds;
    stats.decision_map_photons = decision_owned_.size();
    if (context.log && context.first_of_run)
        *context.log << "photons: decision map of " << decision_settings.count << " photons (" << decision_owned_.size()
                     << " stored) in " << seconds << " s: photons.max_radius_mfp's switch is decided on it, apart from "
                     << "the maps it selects (photon/estimate/bounded_radius.h)\n";
}

void PhotonMapIntegrator::set_map_emitted(double emitted) {
    map_emitted_ = emitted;
    if (decision_emitted_ > 0.0) decision_ratio_ = emitted / decision_emitted_;
}

void PhotonMapIntegrator::decide_bound_on(const PhotonMap* map, double emitted_ratio) {
    decision_map_ = map;
    decision_cells_ = map ? PhotonCellCounts(*map) : PhotonCellCounts();
    decision_emitted_ = 0.0;   // not owned: the ratio is given
    decision_ratio_ = emitted_ratio;
}

uint64_t PhotonMapIntegrator::decision_queries() const {
    uint64_t total = 0;
    for (const auto& l : threads_->local) total += l.estimates.decisions;
    return total;
}

std::string PhotonMapIntegrator::gather_used() const { return no_map_ ? "none" : gather_entry(gather_).name; }

uint64_t PhotonMapIntegrator::map_estimates() const {
    uint64_t total = 0;
    for (const auto& l : threads_->local) total += l.map_used;
    return total;
}

void PhotonMapIntegrator::collect(RunStats& stats, std::ostream* log) const {
    stats.integrator_used = integrator_used();
    stats.gather_used = gather_used();
    stats.map_estimates = map_estimates();
    if (owns_maps_) {
        PhotonLedger l = ledger_;
        l.estimates = *stats.map_estimates;
        l.decision_queries = decision_map_ ? decision_queries() : 0;
        stats.photon_ledger = l;
        if (log)
            *log << "photons traced per phase: " << l.pass_maps << " in " << l.passes_traced << " passes' maps ("
                 << l.estimates << " estimates taken from them), " << l.pilot_only << " for the pilot alone, " << l.probe
                 << " in the probe that sized the pilot's map, " << l.decision_map << " in the decision map ("
                 << l.decision_queries << " radius decisions queried it)\n";
    }
    stats.volume_estimates = this->stats();
    if (!radii_log_.radii.empty()) {
        PassRadiiStats r = radii_log_;
        r.schedule = settings_.schedule == KSchedule::fixed ? "fixed" : settings_.schedule == KSchedule::shrink ? "shrink" : "progressive";
        r.alpha_points = settings_.alpha_for(3);
        r.alpha_surfaces = settings_.alpha_for(2);
        r.last = settings_.radii_for_pass(r.last_pass, scene_.has_media(), surface_map_ != nullptr || traces_surface_map());
        stats.pass_radii = r;
    }
    if (pilot_) stats.gather_pilot = pilot_;
    if (auto_stats_) stats.auto_gather = auto_stats_;
    stats.continued_paths = continued_paths();
    if (settings_.extinction == ExtinctionNormalisation::linear) {
        uint64_t fallbacks = 0;
        for (const auto& l : threads_->local) fallbacks += l.estimates.linear_fallbacks;
        stats.linear_fallbacks = fallbacks;
        if (fallbacks && log)
            *log << "linear: " << fallbacks << " of " << stats.volume_estimates->queries << " estimates fell back to the "
                 << "ball normalisation (their linear-corrected sum was negative; photon/estimate/linear_estimate.h)\n";
    }
    if (decision_map_) stats.decision_queries = decision_queries();
    if (log)
        *log << "estimates: " << stats.volume_estimates->to_string() << "; camera paths continued past a collision "
             << "(fewer than k photons within photons.max_radius_mfp, or in the map): " << *stats.continued_paths
             << (decision_map_ ? "; decision map queries: " + std::to_string(*stats.decision_queries) : std::string()) << "\n";
    if (settings_.gather != GatherMode::collision) {
        uint64_t wide = 0, points = 0;
        double wmax = 0.0, wsum = 0.0;
        for (const auto& l : threads_->local) {
            wide += l.march_wide;
            points += l.march_points;
            wmax = std::max(wmax, l.march_weight_max);
            wsum += l.march_weight_sum;
        }
        stats.march_wide_queries = wide;
        if (points > 0) {
            stats.march_weight_max = wmax;
            stats.march_weight_mean = wsum / double(points);
        }
        if (wide > 0 && log)
            *log << "march: " << wide << " march points took NEE and a continued path instead of an estimate (a kNN "
                 << "ball wider than photons.max_radius_mfp = " << settings_.max_radius_mfp
                 << " mean free paths, or fewer than k = " << k_ << " photons in the map); "
                 << stats.volume_estimates->queries << " map queries in all\n";
    }
    if (segment_gather_) segment_gather_->add_to(stats, log);
    const EstimatorStats ss = surface_stats();
    if (ss.queries) {
        stats.surface_estimates = ss;
        if (log) *log << "surface estimates: " << ss.to_string() << "\n";
    }
}

EstimatorStats PhotonMapIntegrator::stats() const {
    EstimatorStats total;
    for (const auto& l : threads_->local) total.merge(l.estimates.stats);
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
    if (no_map_) return continuation_.radiance(camera_ray, rng);
    PassMaps maps = pass_maps(gather_, *map_, surface_map_, decision_ratio_);
    maps.volume_regions = volume_regions_;
    maps.surface_regions = surface_map_ ? surface_regions_ : nullptr;
    return CameraPath(scene_, settings_, maps, both_strategies_).trace(camera_ray, 0, rng, threads_->local.local());
}

CountedOperations counted_operations(const CounterSet& counters) {
    CountedOperations c;
    for (const auto& l : counters) {
        c.queries += double(l.estimates.stats.queries + l.surface_stats.queries + l.estimates.decisions);
        c.rays += double(l.rays);
        c.lookups += double(l.estimates.lookups);
        c.march_weight_max = std::max(c.march_weight_max, l.march_weight_max);
        c.map_used += double(l.map_used);
    }
    return c;
}

bool PhotonMapIntegrator::volume_map_starved() const { return map_->size() < k_; }

PassMaps PhotonMapIntegrator::pass_maps(GatherMode gather, const PhotonMap& volume, const PhotonMap* surface,
                                        double decision_ratio) const {
    const DecisionMap decision{decision_map_, &decision_cells_, decision_ratio};
    return PassMaps{VolumeEstimator{volume, decision, k_, volume_estimator_, max_radius_, settings_.max_radius_mfp,
                                    settings_.extinction, settings_.leaves_group_out(), threads_->ball,
                                    settings_.neighbourhood},
                    surface, &surface_estimator_, k_, max_radius_, gather,
                    gather_entry(gather).build ? segment_gather_.get() : nullptr};
}

double PhotonMapIntegrator::decision_ratio_for(double emitted) const {
    return decision_emitted_ > 0.0 ? emitted / decision_emitted_ : decision_ratio_;
}

void PhotonMapIntegrator::build_segment_gather(std::ostream* log, RunStats* stats) {
    const GatherEntry& entry = gather_entry(settings_.gather);
    SegmentGatherInputs inputs{scene_, settings_, *map_, owned_.beams, k_, max_radius_, beam_scale_};
    segment_gather_ = entry.build(inputs);
    segment_gather_->report_build(stats, log);
    gather_ = segment_gather_->usable() ? entry.mode : GatherMode::march;
}

void PhotonMapIntegrator::retire_segment_gather(RunStats& stats) {
    if (!segment_gather_) return;
    segment_gather_->add_to(stats, nullptr);
    segment_gather_.reset();
}

void PhotonMapIntegrator::choose_gather(const PassContext& context) {
    // Work units per counted operation, in nanoseconds of single-thread work (fitted to bench_photon_map
    // and the photon tracer's benchmarks, BENCHMARKS.md): a kNN query 700 + 280 k, a tracked segment 1000
    // in grids (about one real collision of delta tracking plus the DDA) and 100 in homogeneous media
    // (closed forms), a sigma_t lookup of the ball quadrature 50. Only their ratios matter, and only
    // between candidates whose variance x cost differ by less than the error of these weights.
    bool grids = false;
    for (const auto& m : scene_.media) grids = grids || !dynamic_cast<const HomogeneousMedium*>(m.get());
    const double w_query = 700.0 + 280.0 * double(k_), w_ray = grids ? 1000.0 : 100.0, w_lookup = 50.0;
    constexpr int kSide = 8, kSamples = 16;
    constexpr int kRays = kSide * kSide;
    const GatherMode candidates[] = {GatherMode::collision, GatherMode::march, GatherMode::threshold};
    GatherPilotStats pilot = pilot_ ? *pilot_ : GatherPilotStats{};
    pilot.candidates = {"collision", "march", "auto"};
    pilot.variance.assign(3, 0.0);
    pilot.cost.assign(3, 0.0);

    // Each candidate's work is counted apart from the run's, on counters of its own.
    auto totals = [](const CounterSet& counters, uint64_t& queries, uint64_t& rays, uint64_t& lookups) {
        queries = rays = lookups = 0;
        for (const auto& l : counters) {
            queries += l.estimates.stats.queries + l.surface_stats.queries;
            rays += l.rays;
            lookups += l.estimates.lookups;
        }
    };
    const Camera& camera = scene_.camera;
    const uint64_t seed = mix64(context.seed ^ 0x70696c6f74ULL);   // streams apart from the camera pass's
    std::vector<double> variance(kRays);
    int chosen = 0;
    for (int c = 0; c < 3; ++c) {
        const PassMaps maps = pass_maps(candidates[c], *map_, surface_map_, decision_ratio_);
        const CameraPath path(scene_, settings_, maps, both_strategies_);
        CounterSet counters;
        tbb::parallel_for(0, kRays, [&](int j) {
            Rng rng(seed, context.stream_offset * uint64_t(kRays) + uint64_t(j));
            double mean = 0.0, m2 = 0.0;
            for (int s = 0; s < kSamples; ++s) {
                const double x = (j % kSide + rng.uniform()) / kSide * camera.width();
                const double y = (j / kSide + rng.uniform()) / kSide * camera.height();
                const Rgb l = path.trace(camera.generate_ray(x, y), 0, rng, counters.local());
                const double v = all_finite(l) ? 0.2126 * l[0] + 0.7152 * l[1] + 0.0722 * l[2] : 0.0;
                const double d = v - mean;
                mean += d / (s + 1);
                m2 += d * (v - mean);
            }
            variance[size_t(j)] = m2 / (kSamples - 1);
        });
        uint64_t queries, rays, lookups;
        totals(counters, queries, rays, lookups);
        double v = 0.0;
        for (double x : variance) v += x;
        pilot.variance[size_t(c)] = v / kRays;
        pilot.cost[size_t(c)] = (w_query * double(queries) + w_ray * double(rays) + w_lookup * double(lookups)) / (kRays * kSamples);
    }
    // Least variance x cost; with no variance anywhere (nothing lit in view), least cost.
    for (int c = 1; c < 3; ++c) {
        const double a = pilot.variance[size_t(c)] * pilot.cost[size_t(c)];
        const double b = pilot.variance[size_t(chosen)] * pilot.cost[size_t(chosen)];
        if (a < b || (a == b && pilot.cost[size_t(c)] < pilot.cost[size_t(chosen)])) chosen = c;
    }
    gather_ = candidates[chosen];
    pilot.chosen = pilot.candidates[size_t(chosen)];
    pilot.chosen_count.resize(3, 0);
    ++pilot.chosen_count[size_t(chosen)];
    pilot_ = pilot;
    if (context.log && context.first_of_run) {
        *context.log << "gather: the pilot chose \"" << pilot.chosen << "\" (pilot, " << kRays << " rays x " << kSamples
                     << " samples: variance x cost";
        for (int c = 0; c < 3; ++c)
            *context.log << (c ? ", " : " ") << pilot.candidates[size_t(c)] << " " << pilot.variance[size_t(c)] * pilot.cost[size_t(c)];
        *context.log << ")\n";
    }
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

std::unique_ptr<IntegratorSettings> read_auto_integrator_settings(Params& render, Params& root) {
    auto s = std::make_unique<PhotonMapIntegratorSettings>();
    Params photons = root.table("photons");
    s->settings = PhotonMapSettings::read(render, photons, true);
    photons.finish();
    // The plan chooses between the path tracer and the gathers its pilot measures: a gather that is
    // chosen otherwise cannot be honoured with it.
    const GatherMode g = s->settings.gather;
    if (render.string("integrator", "path") == "auto" && g != GatherMode::automatic && !gather_entry(g).plan_measures) {
        std::string allowed = "\"auto\"";
        for (const GatherEntry& e : gather_entries())
            if (e.plan_measures) allowed += std::string(", \"") + e.name + "\"";
        photons.fail("gather", "render.integrator = \"auto\" chooses between the path tracer and the photon map's "
                               "gathers its pilot measures: photons.gather must be " + allowed +
                               " with it (or set render.integrator = \"photon_map\")");
    }
    return s;
}

const PhotonMapSettings& photon_map_settings(const RunConfig& config) {
    return static_cast<const PhotonMapIntegratorSettings&>(config.settings_for("photon_map")).settings;
}

}  // namespace vpm
