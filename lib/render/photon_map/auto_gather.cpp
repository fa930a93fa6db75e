// photons.gather = "auto": the map-noise pilot and the pass plan (render/plan/pass_plan.h), run once on
// the first pass of a run. A member of PhotonMapIntegrator kept apart from its camera paths.
#include <algorithm>
#include <atomic>
#include <ostream>
#include <sstream>

#include "core/error.h"
#include "core/progress.h"
#include "core/sampling/rng.h"
#include "render/plan/map_noise_pilot.h"
#include "render/photon_map/auto_plan_log.h"
#include "render/plan/no_map_candidate.h"
#include "render/plan/no_map_stop.h"
#include "render/photon_map/photon_map_integrator.h"
#include "render/plan/work_units.h"
#include "scene/media/tracking_counter.h"
#include "render/photon_map/photon_map_stats.h"

namespace vpm {

int PhotonMapIntegrator::samples_per_pass(int configured) const {
    // The "auto" integrator's path tracer under a limit takes passes of one sample per pixel, as
    // render.integrator = "path" does (render/path/path_tracer.h), unless render.passes pins them.
    if (choice_.no_map && path_tracer_sized_passes()) return 1;
    if (choice_.beam_pass && settings_.size_beam_samples) return choice_.beam_pass->spp;
    return choice_.plan && settings_.size_samples ? choice_.plan->spp : configured;
}

bool PhotonMapIntegrator::path_tracer_sized_passes() const {
    return settings_.time_limit > 0.0 && !settings_.passes_given;
}

void PhotonMapIntegrator::plan_auto(const PassContext& context, RunStats& stats) {
    const Timer timer;
    // The whole span is one-off work; what it holds (a probe, the decision map of a run starting at a
    // later pass) counts once, in the span.
    const double one_off_before = photons_.one_off_seconds;
    // The plan is pass 0's, radii included (photons.schedule), whatever pass the run starts at.
    const PassEstimators pass0 = estimators_for_pass(0);
    const WorkUnits w = work_units(scene_, int(pass0.k));
    PlanInputs in;
    in.pixels = double(scene_.camera.width()) * double(scene_.camera.height());
    in.count = settings_.count;
    in.pilot_count = first_map_photons(context, pass0.k, stats);
    // The configured pass: the plan's sizes start from it, and a pass over budget / kPlanMinPasses
    // may still be as large as it (when unsized the plan only picks the gather at these samples).
    in.spp = std::max(1, context.configured_spp);
    in.size_photons = maps_.owns && settings_.size_photons;
    in.size_samples = settings_.size_samples;
    in.budget = settings_.time_limit * kWorkUnitsPerSecond;
    const PilotMaps pilot = pilot_maps(context, in.pilot_count, stats);
    if (pilot.counts && pilot.counts->emitted > 0) {
        const PhotonPassStats& counts = *pilot.counts;
        in.photon_cost = (w.collision * double(counts.collisions) + w.path * double(counts.emitted) +
                          w.stored * double(counts.stored)) / double(counts.emitted);
    }
    const PlanCandidates candidates = plan_candidates();
    // Measured also where the pilot's volume map is empty and no surface map was stored: the gathers'
    // queries then find no photons and continue the path, so they are the continuation plus a photon
    // pass that buys nothing, and the plan drops them (render/plan/no_map_candidate.h) instead of
    // planning photon passes for a black image.
    const bool measured_by_pilot = pilot.volume()->size() > 0 || !(pilot.surface() && pilot.surface()->size() > 0);
    std::vector<GatherMeasurement> measured = measured_by_pilot ? measure_candidates(context, pilot, candidates, pass0, w, in)
                                                                : unmeasured_map_gathers(candidates);
    exclude_maps_that_go_unused(measured);
    count_pilot_work(context, measured, double(pilot.volume()->size()), w, in);
    in.candidates = measured;
    PassPlan plan = plan_passes(in);
    if (!in.size_samples) plan.spp = 0;   // not the plan's: samples_per_pass keeps the configured value
    adopt_plan(context, plan, candidates.gathers[plan.chosen], measured[size_t(plan.chosen)].uses_map, in.pilot_count);
    check_pinned_samples_fit(context, in, measured[size_t(plan.chosen)], stats);
    AutoGatherStats a;
    a.candidates = measured;
    a.photon_cost = in.photon_cost;
    a.chosen = measured[size_t(plan.chosen)].name;
    a.photon_pass = !choice_.no_map;
    a.pilot_count = in.pilot_count;
    a.count = in.size_photons ? plan.count : in.count;
    a.spp = plan.spp;
    a.beta = plan.beta;
    a.beta_measured = plan.beta_measured;
    a.size_photons = in.size_photons;
    a.size_samples = in.size_samples;
    a.score = plan.score;
    a.pilot_work = in.pilot_work + (plan.count > in.pilot_count || choice_.no_map ? in.pilot_map_work : 0.0);
    a.budget = in.budget;
    choice_.auto_stats = a;
    stats.phase("pilot", timer.seconds());
    photons_.one_off_seconds = one_off_before + timer.seconds();
    if (context.log) {
        AutoPlanReport report;
        report.pixels = in.pixels;
        report.chosen_by_pilot = settings_.gather == GatherMode::automatic || settings_.chooses_integrator;
        report.chooses_integrator = settings_.chooses_integrator;
        report.path_misses_light = candidates.path_misses_light;
        report.map_empty = pilot.volume()->size() == 0;
        report.measured_by_pilot = measured_by_pilot;
        report.no_map = choice_.no_map;
        report.one_spp = choice_.no_map && path_tracer_sized_passes();
        log_auto_plan(*context.log, a, report);
    }
}

// The pilot's map is pass 0's, so that every range of passes rendered apart (render.first_pass,
// vpm merge) makes the same plan: a run starting later traces it apart, with pass 0's streams.
// (Its surface map too: planned without it, a run from pass 1 over a floor took the collision
// gather where pass 0's plan took the march, and vpm merge lost the one-machine image.)
PhotonMapIntegrator::PilotMaps PhotonMapIntegrator::pilot_maps(const PassContext& context, int64_t pilot_count,
                                                               RunStats& stats) {
    PilotMaps pilot;
    pilot.run_volume = maps_.volume;
    pilot.run_surface = maps_.surface;
    pilot.counts = PhotonMapStats::of(stats).photons;
    if (!maps_.owns || context.pass == 0) return pilot;
    PassContext c = context;
    c.stream_offset = context.run_stream_offset;
    c.pass = 0;
    c.first_of_run = false;
    c.progress = false;
    c.log = nullptr;
    RunStats pilot_stats;
    PhotonMapSettings pilot_settings = settings_;
    pilot_settings.count = pilot_count;
    pilot.traced = true;
    pilot.traced_surface = traces_surface_map();
    pilot.owned = run_photon_pass(scene_, pilot_settings, c, pilot.traced_surface, pilot_stats, photons_.allocation);
    photons_.ledger.pilot_only += uint64_t(pilot_count);   // pass 0's map, traced for the plan alone
    pilot.counts = PhotonMapStats::of(pilot_stats).photons;
    if (!decision_.map() && wants_decision_map()) trace_decision_map(context, stats);
    return pilot;
}

// The map's gathers photons.gather leaves open (the registry's measured ones for "auto", else the one
// given); the "auto" integrator adds the path tracer ("continue": render/plan/no_map_candidate.h) where
// it can reach the light. The photon-map integrator always estimates from its map.
PhotonMapIntegrator::PlanCandidates PhotonMapIntegrator::plan_candidates() const {
    PlanCandidates out;
    for (const GatherEntry& e : gather_entries()) {
        if (!e.plan_measures || (settings_.gather != GatherMode::automatic && settings_.gather != e.mode)) continue;
        out.pilot.push_back({e.name, true});
        out.gathers.push_back(e.mode);
    }
    out.path_misses_light = path_tracer_misses_light(scene_);
    if (settings_.chooses_integrator && !out.path_misses_light) {
        out.pilot.push_back({kNoMapCandidate, false});
        out.gathers.push_back(GatherMode::collision);
    }
    return out;
}

// Each candidate's camera paths over the pilot's maps and their halves (render/plan/map_noise_pilot.h),
// counted on counters of their own, with the grid tracking counts of its samples.
std::vector<GatherMeasurement> PhotonMapIntegrator::measure_candidates(const PassContext& context, const PilotMaps& pilot,
                                                                       const PlanCandidates& candidates,
                                                                       const PassEstimators& estimators, const WorkUnits& w,
                                                                       PlanInputs& in) const {
    PilotBudget budget;   // render/plan/pilot_budget.h
    if (in.budget > 0.0) {
        budget.per_candidate = in.budget * kPilotBudgetFraction / double(candidates.pilot.size());
        budget.max_pass_cost = in.budget / kPlanMinPasses;
    }
    const PhotonMap* map = pilot.volume();
    const double pilot_emitted = double(in.pilot_count);   // the pilot's maps, full and halves, are decided on as the run's
    MapNoisePilotHooks hooks;
    // Grid tracking counts of the pilot's samples (scene/media/tracking_counter.h): sums, the
    // same whatever the threads' order.
    std::atomic<uint64_t> steps{0}, density_lookups{0}, cells{0};
    CounterSet pilot_counters;
    std::optional<PassMaps> candidate;
    hooks.use = [&](int c, const PhotonMap* m) {
        const bool uses_map = candidates.pilot[size_t(c)].uses_map;
        const double emitted = m == map ? pilot_emitted : pilot_emitted / 2.0;   // a half map: half the walks
        candidate.emplace(pass_maps(estimators, candidates.gathers[size_t(c)], uses_map ? *m : maps_.empty,
                                    uses_map ? pilot.surface() : nullptr, decision_.for_map(emitted)));
    };
    hooks.trace = [&](const Ray& ray, Rng& rng) {
        // One sample runs on one thread: the thread's counts before and after are the sample's.
        const TrackingCounts before = thread_tracking_counts();
        const Rgb l = CameraPath(scene_, settings_, *candidate, both_strategies_).trace(ray, 0, rng, pilot_counters.local());
        const TrackingCounts& after = thread_tracking_counts();
        steps += after.steps - before.steps;
        density_lookups += after.lookups - before.lookups;
        cells += after.cells - before.cells;
        return l;
    };
    hooks.counts = [&] {
        CountedOperations c = counted_operations(pilot_counters);
        c.steps = double(steps.load());
        c.density_lookups = double(density_lookups.load());
        c.cells = double(cells.load());
        return c;
    };
    // Pixels whose rays meet nothing show the background and do not vary (render/plan/pilot_pixels.h).
    hooks.sees = [&](const Ray& ray) {
        SurfaceHit hit;
        return scene_.intersect(ray, kInfinity, hit) || scene_.optical_depth(ray, kInfinity) > 0.0;
    };
    // A query over the pilot's map (pass 0's); the plan adds the price's growth for larger maps.
    const double query = query_price(w, double(map->size()));
    in.query_doubling = w.query_doubling;
    hooks.work = [&](const CountedOperations& c) {
        const double wide = std::max(0.0, c.queries - c.map_used);   // searches whose estimate was not used
        return query * (c.queries - wide) + w.query_wide * wide + w.ray * c.rays + w.lookup * c.lookups + w.step * c.steps +
               w.density_lookup * c.density_lookups + w.cell * c.cells;
    };
    // The candidate without a map stops where it loses by far (render/plan/no_map_stop.h), tested as
    // the plan would score it with the work counted so far taken off the budget.
    hooks.stop = [&](std::vector<GatherMeasurement>& so_far) {
        PlanInputs test = in;
        test.candidates = so_far;
        test.pilot_work += hooks.work(hooks.counts());
        if (context.pass == 0 && maps_.owns) test.pilot_map_work = in.photon_cost * double(in.pilot_count);
        const NoMapStopTest t = no_map_stop_test(test, so_far.size() - 1);
        so_far.back().stop_low_score = t.low_score;
        so_far.back().stop_best_map_score = t.best_map_score;
        return t.stop;
    };
    std::vector<GatherMeasurement> measured = measure_gathers(scene_.camera, *map, candidates.pilot, hooks,
                                                              mix64(context.seed ^ 0x6d61706e6f697365ULL),
                                                              context.run_stream_offset, budget, in.pixels);
    in.pilot_work += hooks.work(hooks.counts());   // every pilot sample, probes and spread grid included
    return measured;
}

// The pilot's counted one-off work (PlanInputs::pilot_work, pilot_map_work), beside its camera samples'
// (measure_candidates): the half maps' kd-trees where a candidate used the map, and the photons
// traced for the plan alone so far (the probe, pass 0's map traced apart, the decision map), at the
// pilot map's work per photon. The pilot map itself is pass 0's unless the plan traces pass 0 again.
void PhotonMapIntegrator::count_pilot_work(const PassContext& context, const std::vector<GatherMeasurement>& measured,
                                           double pilot_stored, const WorkUnits& w, PlanInputs& in) const {
    bool halves = false;
    for (const GatherMeasurement& m : measured) halves = halves || (m.uses_map && !m.dropped && m.per_sample.map_used > 0.0);
    if (halves) in.pilot_work += w.stored * pilot_stored;
    const PhotonLedger& l = photons_.ledger;
    in.pilot_work += in.photon_cost * double(l.probe + l.pilot_only + l.decision_map);
    if (context.pass == 0 && maps_.owns) in.pilot_map_work = in.photon_cost * double(in.pilot_count);
}

// An empty volume map beside a surface map: the gathers cost the same and "continue" is left out
// (the empty map costs nothing and the surface map keeps its use).
std::vector<GatherMeasurement> PhotonMapIntegrator::unmeasured_map_gathers(const PlanCandidates& candidates) {
    std::vector<GatherMeasurement> measured;
    for (const PilotCandidate& c : candidates.pilot) {
        if (!c.uses_map) continue;
        GatherMeasurement g;
        g.name = c.name;
        g.v_map_quarter = -1.0;
        measured.push_back(g);
    }
    return measured;
}

// The plan's gather from this pass on; a plan without the map ("continue") leaves the passes
// photon-free, and pass 0's map, traced before the plan, served its pilot alone.
void PhotonMapIntegrator::adopt_plan(const PassContext& context, const PassPlan& plan, GatherMode gather, bool uses_map,
                                     int64_t pilot_count) {
    choice_.gather = gather;
    choice_.plan = plan;
    if (uses_map) return;
    choice_.no_map = true;   // render/plan/no_map_candidate.h
    if (context.pass == 0 && maps_.owns && photons_.ledger.pass_maps >= uint64_t(pilot_count)) {
        photons_.ledger.pass_maps -= uint64_t(pilot_count);
        photons_.ledger.pilot_only += uint64_t(pilot_count);
        photons_.ledger.passes_traced -= 1;
    }
    maps_.volume = &maps_.empty;
    maps_.surface = nullptr;
}

// render.spp pinned under render.time_limit: the passes hold its samples whatever the limit, so the
// chosen gather's counted work per sample (the pilot's, deterministic) says whether the camera pass
// alone fits: past the limit's contract (time_limit_contract_seconds) the run is refused, past the limit warned about.
void PhotonMapIntegrator::check_pinned_samples_fit(const PassContext& context, const PlanInputs& in,
                                                   const GatherMeasurement& chosen, RunStats& stats) const {
    if (in.size_samples || !(in.budget > 0.0) || chosen.sample_cost <= 0.0) return;
    if (choice_.no_map && path_tracer_sized_passes()) return;   // 1-spp passes: render.spp is no pass size there
    const double work = chosen.sample_cost * in.pixels * double(in.spp);
    if (!(work > in.budget)) return;
    const double contract = time_limit_contract_seconds(settings_.time_limit);
    const bool refused = work > contract * kWorkUnitsPerSecond;
    std::ostringstream s;
    s.precision(3);
    s << "render.time_limit = " << settings_.time_limit << " s: render.spp is set, so every pass holds " << in.spp
      << " samples per pixel, and the camera pass alone counts " << work / kWorkUnitsPerSecond << " s of one core (gather \""
      << chosen.name << "\"), ";
    if (refused) s << "past the " << contract << " s a run under this limit may take (1.2 x limit + 1 s); ";
    else s << "so the first pass overruns the limit; ";
    if (const double fit = std::floor(in.budget / (chosen.sample_cost * in.pixels)); fit >= 1.0) s << "about " << fit << " samples per pixel fit";
    else s << "not one sample per pixel fits";
    if (refused) {
        s << ": set render.spp to fit, --unset render.spp (and render.passes) for the plan to size the pass, or raise render.time_limit";
        throw ConfigError(s.str());
    }
    s << ", or leave render.spp and render.passes unset for the plan to size the pass";
    stats.warn(s.str(), context.log);
}

}  // namespace vpm
