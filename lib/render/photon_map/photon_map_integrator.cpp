#include "render/photon_map/photon_map_integrator.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <ostream>
#include <sstream>

#include <tbb/enumerable_thread_specific.h>

#include "core/error.h"
#include "core/progress.h"
#include "core/sampling/rng.h"
#include "photon/estimate/ball_extinction.h"
#include "render/photon_map/gathers/segment_gather.h"
#include "render/plan/pass_plan.h"
#include "render/plan/pilot_budget.h"
#include "render/plan/work_units.h"
#include "transport/single_scattering.h"
#include "render/photon_map/photon_map_stats.h"

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
    : scene_(scene), settings_(settings), pass_(settings.unscheduled_estimators()),
      threads_(std::make_unique<ThreadState>(scene)), continuation_(scene, settings.walk) {
    maps_.owns = true;
    maps_.volume = &maps_.owned.volume;
    choice_.gather = initial_gather(settings.gather);
    both_strategies_ = settings.walk.mis && bounces_find_lights(scene);
}

PhotonMapIntegrator::PhotonMapIntegrator(const Scene& scene, const PhotonMapSettings& settings,
                                         const PhotonMap& volume_map, const PhotonMap* surface_map)
    : scene_(scene), settings_(settings), pass_(settings.unscheduled_estimators()),
      threads_(std::make_unique<ThreadState>(scene)), continuation_(scene, settings.walk) {
    maps_.volume = &volume_map;
    maps_.surface = surface_map;
    choice_.gather = initial_gather(settings.gather);
    both_strategies_ = settings.walk.mis && bounces_find_lights(scene);
    pass_ = estimators_for_pass(0);
    if (gather_entry(choice_.gather).build) build_segment_gather(nullptr, nullptr);
}

PhotonMapIntegrator::~PhotonMapIntegrator() = default;

PassEstimators PhotonMapIntegrator::estimators_for_pass(int pass) const {
    return settings_.estimators_for_pass(pass, scene_.has_media(), maps_.surface != nullptr || traces_surface_map());
}

void PhotonMapIntegrator::prepare(const PassContext& context, RunStats& stats) {
    pass_ = estimators_for_pass(context.pass);
    if (radii_log_.radii.size() < RunStats::kPassRecords) {
        radii_log_.pass.push_back(context.pass);
        radii_log_.radii.push_back(settings_.radii_for_pass(context.pass, scene_.has_media(), maps_.surface != nullptr || traces_surface_map()));
    }
    radii_log_.last_pass = context.pass;
    // A run starting at a later pass plans on pass 0's map first: a plan without the map then saves this pass's.
    if (maps_.owns && settings_.plans() && !choice_.plan && context.pass != 0) plan_auto(context, stats);
    if (!maps_.owns) {
        if (settings_.gather == GatherMode::pilot) choose_gather(context);
        if (settings_.plans() && !choice_.plan) plan_auto(context, stats);
        return;
    }
    std::ostream* log = context.first_of_run ? context.log : nullptr;
    const bool surface = traces_surface_map();
    if (choice_.no_map) {   // render/plan/no_map_candidate.h: the plan found the map not worth its pass
        maps_.owned = PhotonMaps();
        maps_.surface = nullptr;
    } else if (scene_.has_media() || surface) {
        // Pass 0 of an auto plan is first traced at photons.count: the pilot's map, which the plan is made on.
        trace_maps(context, choice_.plan ? choice_.plan->count : first_map_photons(context, pass_.k, stats), surface, stats);
        if (!decision_.map() && wants_decision_map()) trace_decision_map(context, stats);
        // k above the stored count: say so once per run (the maps are then not queried).
        const bool volume_short = scene_.has_media() && !gather_entry(settings_.gather).stores_beams && volume_map_starved();
        const bool surface_short = maps_.surface && maps_.surface->size() < pass_.k;
        if ((volume_short || surface_short) && !photons_.warned_k) {
            photons_.warned_k = true;   // in the run record too: under -q a starved map would be path traced unseen
            std::ostringstream w;
            w << "photons.k = " << pass_.k << " exceeds the " << (volume_short ? maps_.volume->size() : maps_.surface->size())
              << (volume_short ? " volume" : " surface") << " photons stored in pass " << context.pass
              << ": no estimate can use k photons, so camera paths are path traced past every "
              << (volume_short ? "medium collision" : "surface hit") << " instead (lower photons.k or raise photons.count)";
            stats.warn(w.str(), context.log);
        }
        if (gather_entry(settings_.gather).build) build_segment_gather(log, &stats);
    } else if (log) {
        *log << "photons: no media and no surface map, so no photon pass\n";
    }
    if (!scene_.has_media() && log) *log << "photons: no media, so the volume photon map is empty\n";
    if (settings_.gather == GatherMode::pilot) choose_gather(context);
    if (settings_.plans() && !choice_.plan) {
        plan_auto(context, stats);
        // Rendered with the pilot's small map, pass 0 would keep that map's bias and noise in the
        // image (all of it where the time limit allows one pass): it is traced again at the plan's
        // size, as every later pass is, and as a run starting at a later pass renders it.
        if (!choice_.no_map && choice_.plan->count > photons_.first_map && (scene_.has_media() || surface)) {
            if (log)
                *log << "photons: pass 0 traced again with the plan's " << choice_.plan->count << " photons (the pilot's "
                     << photons_.first_map << " only chose the plan)\n";
            photons_.one_off_seconds += photons_.last_trace_seconds;   // the pilot's map
            photons_.ledger.pass_maps -= uint64_t(photons_.first_map);   // it served the pilot alone
            photons_.ledger.pilot_only += uint64_t(photons_.first_map);
            photons_.ledger.passes_traced -= 1;
            trace_maps(context, choice_.plan->count, surface, stats);
        }
    }
    if (scene_.uses_embree() && !surface && log)
        *log << "photons: final_gather = true, so no surface photon map (paths continue through surfaces)\n";
}

int64_t PhotonMapIntegrator::first_map_photons(const PassContext& context, size_t k, RunStats& stats) {
    if (photons_.first_map > 0) return photons_.first_map;
    photons_.first_map = settings_.count;
    if (maps_.owns && settings_.size_photons && scene_.has_media()) {
        const Timer probe_timer;
        const PilotPhotonCount p = pilot_photon_count(scene_, settings_, context, traces_surface_map(), photons_.allocation);
        photons_.one_off_seconds += probe_timer.seconds();
        photons_.first_map = p.count;
        photons_.ledger.probe += uint64_t(p.probe_photons);
        if (context.log && context.first_of_run && p.count < settings_.count) {
            *context.log << "photons: the pilot's map of " << p.count << " photons, not photons.count = " << settings_.count
                         << ": a probe of " << p.probe_photons << " stored " << p.stored_per_photon << " per photon, and ";
            if (p.held_by_limit)
                *context.log << "its photon pass may count " << kPilotBudgetFraction << " of render.time_limit";
            else
                *context.log << kPilotStoredPhotons << " stored are what the pilot needs";
            *context.log << " (render/photon_map/photon_pass.h)\n";
        }
    }
    if (maps_.owns && settings_.sizes_beam_pass() && scene_.has_media()) {
        if (!choice_.beam_pass) plan_beam_pass(context, stats);
        photons_.first_map = choice_.beam_pass->count;
        return photons_.first_map;   // the pilots' counted work also judged a pinned count
    }
    if (maps_.owns && !settings_.size_photons && settings_.time_limit > 0.0 && scene_.has_media())
        check_pinned_count_fits(context, k, stats);
    return photons_.first_map;
}

void PhotonMapIntegrator::trace_maps(const PassContext& context, int64_t count, bool surface, RunStats& stats) {
    retire_segment_gather(stats);   // its structure points into the last pass's map
    maps_.owned = PhotonMaps();   // one map in memory at a time: free the last pass's first
    PhotonMapSettings pass_settings = settings_;
    pass_settings.count = count;
    const Timer timer;
    maps_.owned = run_photon_pass(scene_, pass_settings, context, surface, stats, photons_.allocation);
    photons_.last_trace_seconds = timer.seconds();
    photons_.ledger.pass_maps += uint64_t(count);
    photons_.ledger.passes_traced += 1;
    maps_.surface = surface ? &maps_.owned.surface : nullptr;
    use_regions(maps_.owned.volume_regions.empty() ? nullptr : &maps_.owned.volume_regions,
                maps_.owned.surface_regions.empty() ? nullptr : &maps_.owned.surface_regions);
    decision_.set_map_emitted(double(count));
}

void PhotonMapIntegrator::use_regions(const RegionPhotonMaps* volume, const RegionPhotonMaps* surface) {
    maps_.volume_regions = volume;
    maps_.surface_regions = surface;
    // A segment gather built over the maps given to the constructor: built again, split by region.
    if (!maps_.owns && segment_gather_) build_segment_gather(nullptr, nullptr);
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
    decision_settings.count = std::max<int64_t>(1, settings_.count / RunDecisionMap::kShare);
    // The run's photons per light (traced after its first map, which set them).
    decision_.own(std::move(run_photon_pass(scene_, decision_settings, c, false, traced, photons_.allocation).volume),
                  double(decision_settings.count));
    photons_.ledger.decision_map += uint64_t(decision_settings.count);
    double seconds = 0.0;
    for (const PhaseStats& phase : traced.phases) seconds += phase.seconds;
    stats.phase("decision_map", seconds);
    photons_.one_off_seconds += seconds;
    PhotonMapStats::in(stats).decision_map_photons = decision_.map()->size();
    if (context.log && context.first_of_run)
        *context.log << "photons: decision map of " << decision_settings.count << " photons (" << decision_.map()->size()
                     << " stored) in " << seconds << " s: photons.max_radius_mfp's switch is decided on it, apart from "
                     << "the maps it selects (photon/estimate/bounded_radius.h)\n";
}

void PhotonMapIntegrator::decide_bound_on(const PhotonMap* map, double emitted_ratio) { decision_.use(map, emitted_ratio); }

CameraTotals PhotonMapIntegrator::totals() const { return sum_counters(threads_->local); }
uint64_t PhotonMapIntegrator::decision_queries() const { return totals().estimates.decisions; }
uint64_t PhotonMapIntegrator::map_estimates() const { return totals().map_used; }
EstimatorStats PhotonMapIntegrator::stats() const { return totals().estimates.stats; }
uint64_t PhotonMapIntegrator::continued_paths() const { return totals().continued; }
EstimatorStats PhotonMapIntegrator::surface_stats() const { return totals().surface_stats; }
std::string PhotonMapIntegrator::gather_used() const { return choice_.no_map ? "none" : gather_entry(choice_.gather).name; }

Rgb PhotonMapIntegrator::radiance(const Ray& camera_ray, Rng& rng) const {
    if (choice_.no_map) return continuation_.radiance(camera_ray, rng);
    const PassMaps maps = pass_maps(pass_, choice_.gather, *maps_.volume, maps_.surface, decision_.view(), maps_.volume_regions,
                                    maps_.surface ? maps_.surface_regions : nullptr);
    return CameraPath(scene_, settings_, maps, both_strategies_).trace(camera_ray, 0, rng, threads_->local.local());
}

CountedOperations counted_operations(const CounterSet& counters) {
    const CameraTotals t = sum_counters(counters);
    CountedOperations c;
    c.queries = double(t.estimates.stats.queries + t.surface_stats.queries + t.estimates.decisions);
    c.rays = double(t.rays);
    c.lookups = double(t.estimates.lookups);
    c.march_weight_max = t.march_weight_max;
    c.map_used = double(t.map_used);
    return c;
}

bool PhotonMapIntegrator::volume_map_starved() const { return maps_.volume->size() < pass_.k; }

PassMaps PhotonMapIntegrator::pass_maps(const PassEstimators& e, GatherMode gather, const PhotonMap& volume,
                                        const PhotonMap* surface, const DecisionMap& decision,
                                        const RegionPhotonMaps* volume_regions, const RegionPhotonMaps* surface_regions) const {
    return PassMaps{VolumeEstimator{volume, decision, e.k, e.volume, e.max_radius, settings_.max_radius_mfp,
                                    settings_.extinction, settings_.leaves_group_out(), threads_->ball,
                                    settings_.neighbourhood},
                    surface, &e.surface, e.k, e.max_radius, gather,
                    gather_entry(gather).build ? segment_gather_.get() : nullptr, volume_regions, surface_regions};
}

void PhotonMapIntegrator::build_segment_gather(std::ostream* log, RunStats* stats) {
    const GatherEntry& entry = gather_entry(settings_.gather);
    SegmentGatherInputs inputs{scene_, settings_, *maps_.volume, maps_.owned.beams, pass_.k, pass_.max_radius, pass_.beam_scale,
                               maps_.volume_regions,
                               maps_.owned.beam_regions.empty() ? nullptr : &maps_.owned.beam_regions};
    segment_gather_ = entry.build(inputs);
    segment_gather_->report_build(stats, log);
    // Without media no segment is gathered: the record keeps the gather the user set.
    choice_.gather = segment_gather_->usable() || !scene_.has_media() ? entry.mode : GatherMode::march;
}

void PhotonMapIntegrator::retire_segment_gather(RunStats& stats) {
    if (!segment_gather_) return;
    segment_gather_->add_to(stats, nullptr);
    segment_gather_.reset();
}

}  // namespace vpm
