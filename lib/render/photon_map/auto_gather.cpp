// photons.gather = "auto": the map-noise pilot and the pass plan (render/plan/pass_plan.h), run once on
// the first pass of a run. A member of PhotonMapIntegrator kept apart from its camera paths.
#include <algorithm>
#include <atomic>
#include <ostream>
#include <sstream>

#include "core/progress.h"
#include "core/rng.h"
#include "render/plan/map_noise_pilot.h"
#include "render/plan/no_map_candidate.h"
#include "render/photon_map/photon_map_integrator.h"
#include "render/plan/work_units.h"
#include "scene/media/tracking_counter.h"

namespace vpm {

int PhotonMapIntegrator::samples_per_pass(int configured) const {
    // The "auto" integrator's path tracer under a limit takes passes of one sample per pixel, as
    // render.integrator = "path" does (render/path/path_tracer.h), unless render.passes pins them.
    if (no_map_ && path_tracer_sized_passes()) return 1;
    if (beam_pass_ && settings_.size_beam_samples) return beam_pass_->spp;
    return plan_ && settings_.size_samples ? plan_->spp : configured;
}

bool PhotonMapIntegrator::path_tracer_sized_passes() const {
    return settings_.time_limit > 0.0 && !settings_.passes_given;
}

void PhotonMapIntegrator::plan_auto(const PassContext& context, RunStats& stats) {
    const Timer timer;
    // The whole span is one-off work; what it holds (a probe, the decision map of a run starting at a
    // later pass) counts once, in the span.
    const double one_off_before = one_off_seconds_;
    // The plan is pass 0's, radii included (photons.schedule), whatever pass the run starts at.
    struct PassRadiiRestore {
        PhotonMapIntegrator& self;
        int pass;
        ~PassRadiiRestore() { self.schedule_pass(pass); }
    } restore{*this, context.pass};
    schedule_pass(0);
    const WorkUnits w = work_units(scene_, int(k_));
    PlanInputs in;
    in.pixels = double(scene_.camera.width()) * double(scene_.camera.height());
    in.count = settings_.count;
    in.pilot_count = first_map_photons(context, stats);
    // The configured pass: the plan's sizes start from it, and a pass over budget / kPlanMinPasses
    // may still be as large as it (when unsized the plan only picks the gather at these samples).
    in.spp = std::max(1, context.configured_spp);
    in.size_photons = owns_maps_ && settings_.size_photons;
    in.size_samples = settings_.size_samples;
    in.budget = settings_.time_limit * kWorkUnitsPerSecond;
    // The pilot's map is pass 0's, so that every range of passes rendered apart (render.first_pass,
    // vpm merge) makes the same plan: a run starting later traces it apart, with pass 0's streams.
    // (Its surface map too: planned without it, a run from pass 1 over a floor took the collision
    // gather where pass 0's plan took the march, and vpm merge lost the one-machine image.)
    PhotonMaps pilot_maps;
    const PhotonMap* map = map_;
    const PhotonMap* pilot_surface = surface_map_;
    std::optional<PhotonPassStats> counts = stats.photons;
    if (owns_maps_ && context.pass != 0) {
        PassContext c = context;
        c.stream_offset = context.run_stream_offset;
        c.pass = 0;
        c.first_of_run = false;
        c.progress = false;
        c.log = nullptr;
        RunStats pilot_stats;
        PhotonMapSettings pilot_settings = settings_;
        pilot_settings.count = in.pilot_count;
        const bool surface = traces_surface_map();
        pilot_maps = run_photon_pass(scene_, pilot_settings, c, surface, pilot_stats, allocation_);
        ledger_.pilot_only += uint64_t(in.pilot_count);   // pass 0's map, traced for the plan alone
        map = &pilot_maps.volume;
        pilot_surface = surface ? &pilot_maps.surface : nullptr;
        counts = pilot_stats.photons;
        if (!decision_map_ && wants_decision_map()) trace_decision_map(context, stats);
    }
    // The pilot's maps, full and halves, are decided on as the run's (photon/estimate/bounded_radius.h).
    const double pilot_emitted = double(in.pilot_count);
    if (counts && counts->emitted > 0)
        in.photon_cost = (w.collision * double(counts->collisions) + w.path * double(counts->emitted) +
                          w.stored * double(counts->stored)) / double(counts->emitted);
    // The map's gathers photons.gather leaves open (the registry's measured ones for "auto", else the one given); the "auto"
    // integrator adds the path tracer ("continue": render/plan/no_map_candidate.h). The photon-map
    // integrator always estimates from its map.
    std::vector<PilotCandidate> candidates;
    std::vector<GatherMode> gathers;
    for (const GatherEntry& e : gather_entries()) {
        if (!e.plan_measures || (settings_.gather != GatherMode::automatic && settings_.gather != e.mode)) continue;
        candidates.push_back({e.name, true});
        gathers.push_back(e.mode);
    }
    const bool path_misses_light = path_tracer_misses_light(scene_);
    if (settings_.chooses_integrator && !path_misses_light) {
        candidates.push_back({kNoMapCandidate, false});
        gathers.push_back(GatherMode::collision);
    }
    std::vector<GatherMeasurement> measured;
    PilotBudget budget;   // render/plan/pilot_budget.h
    if (in.budget > 0.0) {
        budget.per_candidate = in.budget * kPilotBudgetFraction / double(candidates.size());
        budget.max_pass_cost = in.budget / kPlanMinPasses;
    }
    // Measured also where the pilot's volume map is empty and no surface map was stored: the gathers'
    // queries then find no photons and continue the path, so they are the continuation plus a photon
    // pass that buys nothing, and the plan drops them (render/plan/no_map_candidate.h) instead of
    // planning photon passes for a black image.
    const bool measured_by_pilot = map->size() > 0 || !(pilot_surface && pilot_surface->size() > 0);
    if (measured_by_pilot) {
        MapNoisePilotHooks hooks;
        // Grid tracking counts of the pilot's samples (scene/media/tracking_counter.h): sums, the
        // same whatever the threads' order.
        std::atomic<uint64_t> steps{0}, density_lookups{0}, cells{0};
        // Each candidate's camera paths over the pilot's maps (or a half of them), counted on counters of their own.
        CounterSet pilot_counters;
        std::optional<PassMaps> candidate;
        hooks.use = [&](int c, const PhotonMap* m) {
            const bool uses_map = candidates[size_t(c)].uses_map;
            const double emitted = m == map ? pilot_emitted : pilot_emitted / 2.0;   // a half map: half the walks
            candidate.emplace(pass_maps(gathers[c], uses_map ? *m : empty_map_, uses_map ? pilot_surface : nullptr,
                                        decision_ratio_for(emitted)));
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
        measured = measure_gathers(scene_.camera, *map, candidates, hooks, mix64(context.seed ^ 0x6d61706e6f697365ULL),
                                   context.run_stream_offset, budget, in.pixels);
    } else {
        // An empty volume map beside a surface map: the gathers cost the same and "continue" is left
        // out (the empty map costs nothing and the surface map keeps its use).
        for (size_t c = 0; c < candidates.size(); ++c) {
            if (!candidates[c].uses_map) continue;
            GatherMeasurement g;
            g.name = candidates[c].name;
            g.v_map_quarter = -1.0;
            measured.push_back(g);
        }
    }
    exclude_maps_that_go_unused(measured);
    in.candidates = measured;
    PassPlan plan = plan_passes(in);
    if (!in.size_samples) plan.spp = 0;   // not the plan's: samples_per_pass keeps the configured value
    gather_ = gathers[plan.chosen];
    plan_ = plan;
    if (!measured[size_t(plan.chosen)].uses_map) {   // render/plan/no_map_candidate.h: from this pass on
        no_map_ = true;
        if (context.pass == 0 && owns_maps_ && ledger_.pass_maps >= uint64_t(in.pilot_count)) {   // pass 0's map served the pilot only
            ledger_.pass_maps -= uint64_t(in.pilot_count);
            ledger_.pilot_only += uint64_t(in.pilot_count);
            ledger_.passes_traced -= 1;
        }
        map_ = &empty_map_;
        surface_map_ = nullptr;
    }
    warn_if_pinned_samples_overrun(context, in, measured[size_t(plan.chosen)], stats);
    AutoGatherStats a;
    a.candidates = measured;
    a.photon_cost = in.photon_cost;
    a.chosen = measured[size_t(plan.chosen)].name;
    a.photon_pass = !no_map_;
    a.pilot_count = in.pilot_count;
    a.count = in.size_photons ? plan.count : in.count;
    a.spp = plan.spp;
    a.beta = plan.beta;
    a.beta_measured = plan.beta_measured;
    a.size_photons = in.size_photons;
    a.size_samples = in.size_samples;
    a.score = plan.score;
    auto_stats_ = a;
    stats.phase("pilot", timer.seconds());
    one_off_seconds_ = one_off_before + timer.seconds();
    if (context.log) {
        std::ostream& log = *context.log;
        // One short line with the choice, then one indented line per candidate with its figures.
        if (settings_.gather == GatherMode::automatic || settings_.chooses_integrator)
            log << "gather: auto chose \"" << a.chosen << "\" of " << measured.size() << " candidates";
        else
            log << "gather: \"" << a.chosen << "\" (photons.gather), measured to size the passes under render.time_limit";
        log << " (pilot: "
            << kPilotSide * kPilotSide << " pixels x up to " << kPilotSamples << " samples with the map and its halves, up to "
            << kNoMapPilotSamples << " without a map; work " << in.photon_cost << " per photon)\n";
        if (map->size() == 0)
            log << (measured_by_pilot ? "  the volume map is empty: its queries continue the path\n"
                                      : "  the volume map is empty, nothing to measure\n");
        for (const auto& m : measured) {
            log << "  " << m.name << ": ";
            if (m.dropped) {
                log << "dropped after its probe (a pass of one sample, " << in.pixels * m.sample_cost
                    << " work units, exceeds half the budget), work " << m.sample_cost << " per sample\n";
                continue;
            }
            log << m.samples << " samples, per-sample variance " << m.v_camera << " (charged at "
                << 1.0 + kPlanVarianceSigmas * m.v_camera_rel_se << "x: its upper bound), map variance at N/2 " << m.v_map_half << " +- " << m.v_map_half_se
                << ", bias " << m.bias_mean << " +- " << m.bias_se << " (squared, charged: " << m.bias2 << "), mean " << m.mean << " +- " << m.mean_se
                << (m.max_weight > kPlanMaxMarchWeight ? ", not trusted: march weights up to " + std::to_string(m.max_weight) : std::string())
                << ", work " << m.sample_cost << " per sample, map estimates used " << m.per_sample.map_used << " per sample";
            if (m.uses_map && m.excluded)
                log << " (not a choice: it almost never used the map, so it is the continuation plus a photon pass, render/plan/no_map_candidate.h)";
            if (!m.uses_map)
                log << ", its largest 1/1024 samples hold " << m.tail_share << " of its variance";
            log << "\n";
        }
        if (settings_.chooses_integrator && path_misses_light)
            log << "integrator: auto keeps the photon map: the scene has a point, spot or directional light and a mirror "
                   "or glass surface, whose light the path tracer cannot reach (render.integrator = \"path\" renders it "
                   "anyway)\n";
        if (settings_.chooses_integrator && !path_misses_light) {
            // The figures behind the choice: each candidate's error^2 x work (pass_plan.h), the best map gather's against the path tracer's.
            double best_map = kInfinity, path = kInfinity;
            std::string best_name = "none";
            for (size_t c = 0; c < measured.size(); ++c) {
                if (!measured[c].uses_map) path = plan.score[c];
                else if (plan.score[c] < best_map || best_name == "none") {
                    best_map = plan.score[c];
                    best_name = measured[c].name;
                }
            }
            log << "integrator: auto chose " << (no_map_ ? "the path tracer" : "the photon map (gather \"" + a.chosen + "\")")
                << ": error^2 x work " << (no_map_ ? path : best_map) << " against " << (no_map_ ? best_map : path) << " for "
                << (no_map_ ? "the photon map's best gather (\"" + best_name + "\")" : std::string("the path tracer"))
                << " (render.integrator = \"photon_map\" or \"path\" pins it)\n";
        }
        if (no_map_)
            log << "photons: no photon pass after this one: the map " << (measured[0].per_sample.map_used > 0.0 ? "did not pay for its pass" : "was never used (every kNN ball wider than photons.max_radius_mfp)")
                << ", so every pass, this one included, is the path tracer's (the same estimator, unbiased)\n";
        const bool one_spp = no_map_ && path_tracer_sized_passes();
        if (in.size_photons || in.size_samples || one_spp)
            log << "passes: " << (no_map_ ? std::string("no photons") : std::to_string(a.count) + " photons per pass (" + (in.size_photons ? "sized" : "photons.count") + ")")
                << ", " << (one_spp ? std::string("1 sample per pass (the path tracer's passes under render.time_limit)")
                            : in.size_samples ? std::to_string(plan.spp) + " samples per pass (sized)" : std::string("render.spp samples per pass (given)"))
                << ", the map's variance taken as N^-" << plan.beta << (plan.beta_measured ? " (measured)" : " (assumed)") << "\n";
    }
}

// render.spp pinned under render.time_limit: the passes hold its samples whatever the limit, so the
// chosen gather's counted work per sample (the pilot's, deterministic) says whether the camera pass alone fits.
void PhotonMapIntegrator::warn_if_pinned_samples_overrun(const PassContext& context, const PlanInputs& in,
                                                        const GatherMeasurement& chosen, RunStats& stats) const {
    if (in.size_samples || !(in.budget > 0.0) || chosen.sample_cost <= 0.0) return;
    if (no_map_ && path_tracer_sized_passes()) return;   // 1-spp passes: render.spp is no pass size there
    const double work = chosen.sample_cost * in.pixels * double(in.spp);
    if (!(work > in.budget)) return;
    std::ostringstream s;
    s.precision(3);
    s << "render.time_limit = " << settings_.time_limit << " s: render.spp is set, so every pass holds " << in.spp
      << " samples per pixel, and the camera pass alone counts " << work / kWorkUnitsPerSecond
      << " s of one core (gather \"" << chosen.name << "\"), so the first pass overruns the limit; ";
    if (const double fit = std::floor(in.budget / (chosen.sample_cost * in.pixels)); fit >= 1.0) s << "about " << fit << " samples per pixel fit";
    else s << "not one sample per pixel fits";
    s << ", or leave render.spp and render.passes unset for the plan to size the pass";
    stats.warn(s.str(), context.log);
}

}  // namespace vpm
