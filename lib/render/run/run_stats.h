#pragma once
// The typed statistics of one run. Integrators and the run fill them; analysis code (sweeps,
// the stress matrix, benchmarks) reads them as they are; write_run_stats serialises them into
// the run's JSON record, once, under the keys docs/rendering.md documents.
#include <cstdint>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include "photon/estimate/estimators.h"
#include "photon/trace/photon_tracer.h"
#include "render/plan/pass_plan.h"
#include "render/photon_map/gathers/point_beam_gather_stats.h"
#include "render/photon_map/photon_map_settings.h"
#include "render/photon_map/gathers/photon_beams_gather_stats.h"
#include "render/run/render_loop.h"

namespace vpm {

class RunRecord;

// Wall time of a phase and the process's peak resident memory when it ended.
struct PhaseStats {
    std::string name;
    double seconds = 0.0;
    uint64_t peak_rss_bytes = 0;
};

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

// One pass of a run: its photon pass (if any) and its share of the camera samples.
struct PassStats {
    double seconds = 0.0;      // wall time of the pass, all phases
    double elapsed = 0.0;      // since the run started, at the end of the pass
    int spp = 0;
    double image_mean = 0.0;   // mean over pixels and channels of this pass's image alone
};

// Every pass of a run, summarised in constant memory (a time-limited run may make millions).
struct PassSummary {
    uint64_t count = 0;
    int spp = 0;                      // samples per pixel of each pass
    double seconds_total = 0.0, seconds_min = 0.0, seconds_max = 0.0;
    double elapsed = 0.0;             // at the end of the last pass
    double image_mean_mean = 0.0;     // mean over passes of PassStats::image_mean
    double image_mean_m2 = 0.0;       // Welford's sum of squared deviations of it
    void add(const PassStats& p);
    double image_mean_std() const;    // sample standard deviation over passes (0 for one)
};

// photons.gather = "pilot": what each pass's pilot measured (render/photon_map/gather_pilot.cpp) and chose.
struct GatherPilotStats {
    std::vector<std::string> candidates;   // "collision", "march", "auto"
    std::vector<double> variance;          // mean per-sample variance of the luminance over the pilot rays
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
    std::vector<double> score;     // per candidate: the plan's error^2 x work at its best pass sizes (infinite: not a choice)
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

struct RunStats {
    // Passes are bounded in memory and in the sidecar: `passes` holds the first kPassRecords of
    // them, `pass_summary` all of them (vpm render streams every pass to OUT.passes.csv).
    static constexpr size_t kPassRecords = 256;
    std::vector<PhaseStats> phases;
    std::vector<PassStats> passes;    // the first kPassRecords passes
    PassSummary pass_summary;         // every pass
    int first_pass = 0;   // render.first_pass: passes are first_pass .. first_pass + pass_summary.count - 1
    RenderStats render;
    // What ran (the sidecar's top-level "integrator_used", "gather_used", "map_estimates"): the
    // integrator that rendered ("path" or "photon_map"; for render.integrator = "auto" its plan's
    // choice), the photon map's gather ("collision", "march", "threshold", "beam"; "none" without a
    // map) and the estimates its camera passes took from a map (volume or surface).
    std::string integrator_used;
    std::optional<std::string> gather_used;
    std::optional<uint64_t> map_estimates;
    std::optional<PhotonLedger> photon_ledger;         // photon map: photons traced per phase
    std::optional<PhotonPassStats> photons;            // integrators with a photon pass
    std::optional<EstimatorStats> volume_estimates;    // volume photon map queries
    std::optional<EstimatorStats> surface_estimates;   // surface photon map queries (when any)
    std::optional<uint64_t> continued_paths;           // photon map: camera paths continued (bounded radius)
    std::optional<uint64_t> linear_fallbacks;          // photons.extinction = "linear": negative sums replaced
    std::optional<uint64_t> decision_queries;          // photon map: queries of the bound's decision map
    std::optional<uint64_t> decision_map_photons;      // photon map: the decision map's stored photons
    std::optional<uint64_t> march_wide_queries;        // gather = "march": queries beyond max_radius_mfp
    std::optional<PassRadiiStats> pass_radii;          // photon map: photons.schedule per pass
    std::optional<GatherPilotStats> gather_pilot;      // gather = "pilot"
    std::optional<AutoGatherStats> auto_gather;        // gather = "auto"
    std::optional<PointBeamGatherStats> beam;               // gather = "beam": memory, build, queries
    std::optional<PhotonBeamsGatherStats> photon_beams; // gather = "photon_beams": beams, build, queries
    // March points' weights relative to their value where the majorant is exact (T sigma_t /
    // (mu e^-tau_mu) = 1 in homogeneous media): the largest and the mean, over the camera pass.
    std::optional<double> march_weight_max, march_weight_mean;
    // What the run could not honour and went on with (the sidecar's "warnings", also logged).
    std::vector<std::string> warnings;
    // Keeps `message` in warnings and writes "warning: message" on log (when given).
    void warn(const std::string& message, std::ostream* log);

    // Counts a pass in the summary and keeps its record while fewer than kPassRecords are kept.
    void add_pass(const PassStats& p);
    uint64_t pass_count() const { return pass_summary.count; }
    // Adds `seconds` to a phase (phases repeat once per pass), with the peak resident memory now.
    void phase(const std::string& name, double seconds);
    // Counts and energy of a photon pass, summed over passes.
    void add_photon_pass(const PhotonPassStats& p);
    // Seconds of a phase; 0 when the run had no such phase.
    double seconds(const std::string& name) const;
};

// Writes every statistic into `record` (phases.*, render.*, photons.*).
void write_run_stats(const RunStats& stats, RunRecord& record);

}  // namespace vpm
