#pragma once
// The photon-map integrator's section of a run's statistics: its photon passes, the estimates its
// camera passes took, the decision map, the radii per pass and what the automatic choices measured.
// The segment gathers keep sections of their own (gathers/*_stats.h).
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "photon/estimate/estimators.h"
#include "photon/trace/photon_tracer.h"
#include "render/photon_map/photon_map_settings.h"
#include "render/plan/pass_plan.h"
#include "render/run/run_stats.h"

namespace vpm {

// Where one light's photons went (photon/trace/photon_allocation.h, render/photon_map/photon_lights_report.h).
struct LightPhotonReport {
    std::string light;            // describe()
    double weight = 0.0;          // share of the photons
    double power_share = 0.0;
    double importance = 0.0;      // pilot's share of stored power where the camera looks
    LightPhotonStats counts;      // emitted, landed, stored
    bool wasted = false;          // landed / emitted < kWastedLightFraction
    bool reaches_nothing = false; // no direction of the light meets the scene's box: no photons
};

// The photon pass and its kd-trees.
struct PhotonPassStats {
    uint64_t emitted = 0;             // photon paths
    uint64_t stored = 0;              // volume photons
    uint64_t collisions = 0;          // real medium collisions, stored or not
    uint64_t storing_walks = 0;       // photon paths that stored at least one volume photon
    double store_probability = 1.0;   // volume storage probability (after "auto"'s first batch), of the last pass
    uint64_t truncated_paths = 0;
    double paths_per_second = 0.0;
    EnergyBalance energy;
    double projected_map_bytes = 0.0;   // projected before building (records + index)
    double memory_budget_bytes = 0.0;
    bool over_memory_budget = false;
    uint64_t bytes_per_photon = 0;
    uint64_t map_bytes = 0;
    double map_bytes_per_photon = 0.0;
    bool surface_map = false;         // the fields below are set only with a surface map
    uint64_t surface_hits = 0;
    uint64_t surface_stored = 0;
    uint64_t surface_map_bytes = 0;
    std::string allocation;            // "importance" | "power"
    double stored_per_emitted = 0.0;   // (volume + surface records) / emitted
    std::vector<LightPhotonReport> lights;

    // Adds another pass's counts and energy; bytes are the largest of one map (one at a time).
    void merge(const PhotonPassStats& o);
};

// photons.gather = "pilot": what each pass's pilot measured (render/photon_map/gather_pilot.cpp) and chose.
struct GatherPilotStats {
    std::vector<std::string> candidates;   // "collision", "march", "auto"
    std::vector<double> variance;          // mean per-sample relative variance of the luminance over the pilot rays (each / (R^2 + 0.01))
    std::vector<double> cost;              // deterministic work units per sample
    std::string chosen;                    // the last pass's choice
    std::vector<uint64_t> chosen_count;    // passes that chose each candidate (bounded however many passes)
};

// photons.gather = "auto": what the map-noise pilot measured and what the plan chose (render/plan/pass_plan.h).
struct AutoGatherStats {
    std::vector<GatherMeasurement> candidates;
    double photon_cost = 0.0;      // work units per emitted photon
    std::string chosen;
    int64_t pilot_count = 0;       // the pilot map's photons: photons.count, or fewer where walks store many (render/photon_map/photon_pass.h)
    int64_t count = 0;             // photons per pass (pass 0 traced again at it when above pilot_count)
    int spp = 0;                   // samples per pass
    double beta = 1.0;             // V_map ~ N^-beta
    bool beta_measured = false;
    bool size_photons = false, size_samples = false;
    bool photon_pass = true;       // false: "continue" chosen, no photon pass after the pilot's (render/plan/no_map_candidate.h)
    std::vector<double> score;     // per candidate: the plan's relative error^2 x work (render/plan/relative_error.h) at its best pass sizes (infinite: not a choice)
    double budget = 0.0;           // render.time_limit in work units (0: none)
    double pilot_work = 0.0;       // the pilot's counted one-off work the plan took off the budget (render/plan/pass_plan.h: plan_budget)
};

// The photons a photon-map run traced, per phase, and what used them (no work traced and discarded unsaid).
struct PhotonLedger {
    uint64_t pass_maps = 0;        // emitted into the maps the camera passes estimate from
    int64_t passes_traced = 0;     // photon passes behind them
    uint64_t estimates = 0;        // estimates the camera passes took from a map (RunStats::map_estimates)
    uint64_t pilot_only = 0;       // emitted into maps only the plan's pilot used (pass 0's, traced apart or again at the plan's count)
    uint64_t probe = 0;            // emitted by the probe that sized the pilot's map (render/photon_map/photon_pass.h)
    uint64_t decision_map = 0;     // emitted into the radius bound's decision map (photon/estimate/bounded_radius.h)
    uint64_t decision_queries = 0; // its kNN queries
};

// photons.schedule (photon/estimate/radius_schedule.h, docs/progressive.md): each recorded pass's k
// and radius scales, and the last pass's (a pass's radii depend on its index alone).
struct PassRadiiStats {
    std::string schedule;                   // "fixed" | "progressive" | "shrink"
    double alpha_points = 0.0, alpha_surfaces = 0.0;
    std::vector<int> pass;                  // the recorded passes' indices (at most RunStats::kPassRecords)
    std::vector<PassRadii> radii;           // the same passes' k and scales
    int last_pass = 0;
    PassRadii last;
};

struct PhotonMapStats : StatsSectionOf<PhotonMapStats> {
    std::optional<PhotonLedger> photon_ledger;         // photon map: photons traced per phase
    std::optional<PhotonPassStats> photons;            // the photon passes, summed
    std::optional<EstimatorStats> volume_estimates;    // volume photon map queries
    std::optional<EstimatorStats> surface_estimates;   // surface photon map queries (when any)
    std::optional<uint64_t> continued_paths;           // photon map: camera paths continued (bounded radius)
    std::optional<uint64_t> linear_fallbacks;          // photons.extinction = "linear": negative sums replaced
    std::optional<uint64_t> linear_negatives;          // "linear_signed": negative estimates kept
    std::optional<uint64_t> decision_queries;          // photon map: queries of the bound's decision map
    std::optional<uint64_t> decision_map_photons;      // photon map: the decision map's stored photons
    std::optional<uint64_t> march_wide_queries;        // gather = "march": queries beyond max_radius_mfp
    std::optional<PassRadiiStats> pass_radii;          // photon map: photons.schedule per pass
    std::optional<GatherPilotStats> gather_pilot;      // gather = "pilot"
    std::optional<AutoGatherStats> auto_gather;        // gather = "auto"
    // March points' weights relative to their value where the majorant is exact (T sigma_t /
    // (mu e^-tau_mu) = 1 in homogeneous media): the largest and the mean, over the camera pass.
    std::optional<double> march_weight_max, march_weight_mean;

    // Counts and energy of a photon pass, summed over passes.
    void add_photon_pass(const PhotonPassStats& p);
    void write(RunRecord& record) const override;

    // The run's photon-map section; an empty one when the run kept none (no photon map).
    static const PhotonMapStats& of(const RunStats& run);
    // The run's photon-map section, added when absent.
    static PhotonMapStats& in(RunStats& run) { return run.sections.get<PhotonMapStats>(); }
};

}  // namespace vpm
