// The automatic plan's log lines (auto_plan_log.h).
#include "render/photon_map/auto_plan_log.h"

#include <ostream>
#include <string>

#include "core/math.h"
#include "render/plan/map_noise_pilot.h"
#include "render/plan/no_map_stop.h"
#include "render/plan/pass_plan.h"

namespace vpm {
namespace {

void log_candidate(std::ostream& log, const GatherMeasurement& m, double pixels) {
    log << "  " << m.name << ": ";
    if (m.dropped) {
        log << "dropped after its probe (a pass of one sample, " << pixels * m.sample_cost
            << " work units, exceeds half the budget), work " << m.sample_cost << " per sample\n";
        return;
    }
    log << m.samples << " samples, per-sample relative variance " << m.v_camera << " (charged at "
        << 1.0 + kPlanVarianceSigmas * m.v_camera_rel_se << "x: its upper bound), map variance at N/2 " << m.v_map_half << " +- " << m.v_map_half_se
        << ", bias " << m.bias_mean << " +- " << m.bias_se << " (squared, charged: " << m.bias2 << "), mean " << m.mean << " +- " << m.mean_se
        << (m.max_weight > kPlanMaxMarchWeight ? ", not trusted: march weights up to " + std::to_string(m.max_weight) : std::string())
        << ", work " << m.sample_cost << " per sample, map estimates used " << m.per_sample.map_used << " per sample";
    if (m.uses_map && m.excluded)
        log << " (not a choice: it almost never used the map, so it is the continuation plus a photon pass, render/plan/no_map_candidate.h)";
    if (!m.uses_map)
        log << ", its largest 1/1024 samples hold " << m.tail_share << " of its variance";
    if (m.stopped_early)
        log << "; its pilot stopped after " << m.samples << " samples per pixel, losing by far: relative error^2 x work "
            << m.stop_low_score << " at its variance's lower bound (" << variance_lower_factor(m.v_camera_rel_se) << " of the figure read), over "
            << kNoMapStopMargin << "x the best map gather's " << m.stop_best_map_score << " (not a choice, render/plan/no_map_stop.h)";
    log << "\n";
}

// The figures behind the "auto" integrator's choice: each candidate's relative error^2 x work (pass_plan.h),
// the best map gather's against the path tracer's.
void log_integrator_choice(std::ostream& log, const AutoGatherStats& a, bool no_map) {
    const std::vector<GatherMeasurement>& measured = a.candidates;
    double best_map = kInfinity, path = kInfinity;
    std::string best_name = "none";
    for (size_t c = 0; c < measured.size(); ++c) {
        if (!measured[c].uses_map) path = a.score[c];
        else if (a.score[c] < best_map || best_name == "none") {
            best_map = a.score[c];
            best_name = measured[c].name;
        }
    }
    log << "integrator: auto chose " << (no_map ? "the path tracer" : "the photon map (gather \"" + a.chosen + "\")")
        << ": relative error^2 x work " << (no_map ? path : best_map) << " against " << (no_map ? best_map : path) << " for "
        << (no_map ? "the photon map's best gather (\"" + best_name + "\")" : std::string("the path tracer"))
        << " (render.integrator = \"photon_map\" or \"path\" pins it)\n";
}

}  // namespace

void log_auto_plan(std::ostream& log, const AutoGatherStats& a, const AutoPlanReport& r) {
    const std::vector<GatherMeasurement>& measured = a.candidates;
    if (r.chosen_by_pilot)
        log << "gather: auto chose \"" << a.chosen << "\" of " << measured.size() << " candidates";
    else
        log << "gather: \"" << a.chosen << "\" (photons.gather), measured to size the passes under render.time_limit";
    log << " (pilot: "
        << kPilotSide * kPilotSide << " pixels x up to " << kPilotSamples << " samples with the map and its halves, up to "
        << kNoMapPilotSamples << " without a map, stopped early where it loses by far; work " << a.photon_cost << " per photon)\n";
    if (r.map_empty)
        log << (r.measured_by_pilot ? "  the volume map is empty: its queries continue the path\n"
                                    : "  the volume map is empty, nothing to measure\n");
    for (const auto& m : measured) log_candidate(log, m, r.pixels);
    if (r.chooses_integrator && r.path_misses_light)
        log << "integrator: auto keeps the photon map: the scene has a point, spot or directional light and a mirror "
               "or glass surface, whose light the path tracer cannot reach (render.integrator = \"path\" renders it "
               "anyway)\n";
    if (r.chooses_integrator && !r.path_misses_light) log_integrator_choice(log, a, r.no_map);
    if (r.no_map)
        log << "photons: no photon pass after this one: the map " << (measured[0].per_sample.map_used > 0.0 ? "did not pay for its pass" : "was never used (every kNN ball wider than photons.max_radius_mfp)")
            << ", so every pass, this one included, is the path tracer's (the same estimator, unbiased)\n";
    if (a.size_photons || a.size_samples || r.one_spp)
        log << "passes: " << (r.no_map ? std::string("no photons") : std::to_string(a.count) + " photons per pass (" + (a.size_photons ? "sized" : "photons.count") + ")")
            << ", " << (r.one_spp ? std::string("1 sample per pass (the path tracer's passes under render.time_limit)")
                        : a.size_samples ? std::to_string(a.spp) + " samples per pass (sized)" : std::string("render.spp samples per pass (given)"))
            << ", the map's variance taken as N^-" << a.beta << (a.beta_measured ? " (measured)" : " (assumed)") << "\n";
    if (a.budget > 0.0)
        log << "passes: sized for " << (a.budget - a.pilot_work) / kWorkUnitsPerSecond << " s of one core: render.time_limit less the pilot's counted "
            << a.pilot_work / kWorkUnitsPerSecond << " s (its samples and the photons traced for it alone)"
            << (a.pilot_work >= a.budget ? ", which reach the limit: one pass, no larger than the configured one" : "") << "\n";
}

}  // namespace vpm
