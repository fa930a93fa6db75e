#pragma once
// The photon-map integrator (render.integrator = "photon_map", and "auto", whose plan may choose the
// path tracer): the driver of a photon-map run. Per pass it traces the photon maps (photon_pass.h),
// builds what the gather in force needs (gathers/), and hands the camera paths (camera_path.h) one
// read-only view of the pass (PassMaps). Once per run it traces the radius bound's decision map and,
// for the automatic choices, runs the pilot and the plan (auto_gather.cpp, render/plan/). What the
// camera side computes and why: camera_path.h, volume_estimate.h and docs/integrators.md.
#include <memory>
#include <optional>

#include "photon/estimate/bounded_radius.h"
#include "photon/estimate/estimators.h"
#include "photon/map/photon_cell_counts.h"
#include "photon/map/photon_map.h"
#include "render/integrator.h"
#include "render/photon_map/beam_pass_size.h"
#include "render/photon_map/photon_map_settings.h"
#include "render/plan/map_noise_pilot.h"
#include "render/plan/pass_plan.h"
#include "render/plan/work_units.h"
#include "render/path/path_tracer.h"
#include "render/photon_map/photon_pass.h"
#include "render/photon_map/camera_path.h"
#include "render/photon_map/run_decision_map.h"
#include "render/photon_map/volume_estimate.h"
#include "render/run/run_config.h"
#include "transport/mis.h"
#include "render/photon_map/photon_map_stats.h"
#include "scene/scene.h"

namespace vpm {

class SegmentGather;

class PhotonMapIntegrator : public Integrator {
public:
    // Builds its own maps in prepare() (the photon pass).
    PhotonMapIntegrator(const Scene& scene, const PhotonMapSettings& settings);
    // Uses maps built elsewhere (tests, studies); prepare() then does nothing. surface_map: null for
    // none (final gather through surfaces).
    PhotonMapIntegrator(const Scene& scene, const PhotonMapSettings& settings, const PhotonMap& volume_map,
                        const PhotonMap* surface_map = nullptr);
    ~PhotonMapIntegrator() override;

    void prepare(const PassContext& context, RunStats& stats) override;
    Rgb radiance(const Ray& ray, Rng& rng) const override;
    void collect(RunStats& stats, std::ostream* log) const override;
    // "photon_map", or "auto" (photons's settings chooses_integrator): the plan may render the run with
    // the path tracer instead (render/plan/no_map_candidate.h); integrator_used() says which ran.
    std::string name() const override { return settings_.chooses_integrator ? "auto" : "photon_map"; }
    // "path" once the "auto" integrator's plan chose the path tracer, else "photon_map".
    std::string integrator_used() const { return choice_.no_map ? "path" : "photon_map"; }
    // The gather in force, by its registry name (photons.gather's value); "none" without a map.
    std::string gather_used() const;
    // Estimates the camera passes took from a map (volume or surface), not continued past.
    uint64_t map_estimates() const;
    // gather = "auto" under render.time_limit: the plan's samples per pass (render/plan/pass_plan.h).
    int samples_per_pass(int configured) const override;
    // The "auto" integrator's path tracer under render.time_limit without render.passes: passes of 1 spp.
    bool path_tracer_sized_passes() const;
    // Once the "auto" integrator's plan chose "continue" no pass traces photons: the passes may go in groups, and the
    // first pass's photon pass and pilot are not what a later pass costs (render/run/run.cpp).
    bool stateless_passes() const override { return choice_.no_map; }
    double one_off_seconds() const override { return photons_.one_off_seconds; }
    // The gather in force: photons.gather, or what "auto" or "pilot" chose; "march" for a pass whose
    // segment gather had nothing to query.
    GatherMode gather() const { return choice_.gather; }
    const std::optional<GatherPilotStats>& gather_pilot() const { return choice_.pilot; }
    // Counts of each estimator case (knn, fixed radius, ...) over all queries so far.
    EstimatorStats stats() const;
    // Camera paths continued past a collision whose mean-free-path-bounded ball held fewer than
    // k - 1 photons (photons.max_radius_mfp; photon/estimate/bounded_radius.h).
    uint64_t continued_paths() const;
    // The same for the surface map's queries.
    EstimatorStats surface_stats() const;
    // The map photons.max_radius_mfp's switch is decided on (photon/estimate/bounded_radius.h): for maps built
    // elsewhere, `map` (independent of the volume map, null for the switch on the volume map's own
    // list) and the volume map's emitted photons per emitted photon of `map`. prepare() traces its own.
    void decide_bound_on(const PhotonMap* map, double emitted_ratio);
    // Maps built elsewhere, split by region (scene/dielectric_regions.h): the estimates query these
    // by the camera path's region, the maps given to the constructor serve the rest. Null: none.
    void use_regions(const RegionPhotonMaps* volume, const RegionPhotonMaps* surface);
    // kNN queries made on the decision map so far (decisions its cell counts did not settle).
    uint64_t decision_queries() const;

private:
    struct ThreadState;
    // The maps this pass's estimates read: traced by the pass (owns) or built elsewhere.
    struct MapSet {
        bool owns = false;
        PhotonMaps owned;                      // the pass's own (owns)
        const PhotonMap* volume = nullptr;
        const PhotonMap* surface = nullptr;    // null: no surface map (paths bounce off surfaces)
        // Glass interfaces (scene/dielectric_regions.h): the maps per region, null in a scene without
        // closed glass shapes; the camera paths' estimates take their own region's (camera_path.h).
        const RegionPhotonMaps* volume_regions = nullptr;
        const RegionPhotonMaps* surface_regions = nullptr;
        PhotonMap empty;                       // the "continue" candidate's map in the plan's pilot
    };
    // The photons a run traced besides the passes' maps, and what decided their counts.
    struct PhotonAccounts {
        std::optional<LightAllocation> allocation;   // photons per light, from the run's first pass
        int64_t first_map = 0;            // first_map_photons(); 0: not decided yet
        double one_off_seconds = 0.0;     // one_off_seconds(): the probe, the pilot, its map when traced again, the decision map
        double last_trace_seconds = 0.0;  // trace_maps' last photon pass
        PhotonLedger ledger;              // photons traced per phase (RunStats::photon_ledger)
        bool warned_k = false;            // "k exceeds the stored count" is logged once per run
    };
    // The gather in force and what chose it.
    struct GatherChoice {
        GatherMode gather = GatherMode::collision;
        std::optional<GatherPilotStats> pilot;      // gather = "pilot" (gather_pilot.cpp)
        std::optional<PassPlan> plan;               // gather = "auto" or the "auto" integrator (auto_gather.cpp)
        std::optional<AutoGatherStats> auto_stats;
        std::optional<BeamPassSize> beam_pass;      // gather = "photon_beams" or "point_beam" under render.time_limit (beam_pilot.cpp)
        // The plan chose "continue" (render/plan/no_map_candidate.h): no photon pass, and the camera
        // paths are the path tracer's (with an empty map they would draw the same paths in distribution,
        // but pay 1.2-1.5x the path tracer's time per sample for the map's bookkeeping).
        bool no_map = false;
    };
    // The maps the plan's pilot measures on: pass 0's, this pass's own or traced apart for the plan.
    struct PilotMaps {
        const PhotonMap* run_volume = nullptr;
        const PhotonMap* run_surface = nullptr;
        bool traced = false, traced_surface = false;   // pass 0's maps traced apart, in `owned`
        PhotonMaps owned;
        std::optional<PhotonPassStats> counts;   // the photon pass behind them
        const PhotonMap* volume() const { return traced ? &owned.volume : run_volume; }
        const PhotonMap* surface() const { return traced ? (traced_surface ? &owned.surface : nullptr) : run_surface; }
    };
    // The gathers the plan chooses among, with their names as the pilot measures them.
    struct PlanCandidates {
        std::vector<PilotCandidate> pilot;
        std::vector<GatherMode> gathers;
        bool path_misses_light = false;   // render/plan/no_map_candidate.h: no "continue" candidate
    };

    // --- Passes and maps (photon_map_integrator.cpp)
    // Whether passes trace a surface photon map: surfaces, and final_gather off.
    bool traces_surface_map() const;
    // This pass's photon maps with `count` photons (the last pass's freed first).
    void trace_maps(const PassContext& context, int64_t count, bool surface, RunStats& stats);
    // The photons of the run's first map (and of the auto plan's pilot map): photons.count, or fewer
    // where an auto plan sizes the count and walks store many photons each (render/photon_map/photon_pass.h).
    // Decided once per run, on a probe with the run's streams, so every pass range plans alike.
    // k: the pass's (the plan's pass 0's), for the cost of its queries.
    int64_t first_map_photons(const PassContext& context, size_t k, RunStats& stats);
    void check_pinned_count_fits(const PassContext& context, size_t k, RunStats& stats);
    // Whether this run's estimates need a decision map: media, the bound on, a gather that uses it.
    bool wants_decision_map() const;
    // Traces the decision map (once per run) and logs it.
    void trace_decision_map(const PassContext& context, RunStats& stats);
    PassEstimators estimators_for_pass(int pass) const;
    // Whether the volume map is too small for any estimate (the warning in prepare()).
    bool volume_map_starved() const;
    // A segment gather over this pass's maps (logging and timing the build when given); an unusable one
    // (nothing to query) leaves the pass gathering like "march".
    void build_segment_gather(std::ostream* log, RunStats* stats);
    // Adds its counts to the run's statistics and frees it.
    void retire_segment_gather(RunStats& stats);
    // This pass's maps as the camera path reads them, with `gather` in force over `volume` and `surface`
    // (the pass's own, or a pilot's candidates), `decision` (RunDecisionMap's view or for_map) and the
    // maps split by glass region (null: one region).
    PassMaps pass_maps(const PassEstimators& estimators, GatherMode gather, const PhotonMap& volume, const PhotonMap* surface,
                       const DecisionMap& decision, const RegionPhotonMaps* volume_regions = nullptr,
                       const RegionPhotonMaps* surface_regions = nullptr) const;

    // Every thread's camera counts summed.
    CameraTotals totals() const;

    // --- gather = "pilot": this pass's gather by a pilot of its own (gather_pilot.cpp)
    void choose_gather(const PassContext& context);

    // --- gather = "auto" and the "auto" integrator (auto_gather.cpp): on the run's first pass, the
    // map-noise pilot (render/plan/map_noise_pilot.h) measures the candidates and the plan
    // (render/plan/pass_plan.h) picks the gather, and under render.time_limit the photons and samples per pass.
    void plan_auto(const PassContext& context, RunStats& stats);
    PilotMaps pilot_maps(const PassContext& context, int64_t pilot_count, RunStats& stats);
    PlanCandidates plan_candidates() const;
    std::vector<GatherMeasurement> measure_candidates(const PassContext& context, const PilotMaps& pilot,
                                                      const PlanCandidates& candidates, const PassEstimators& estimators,
                                                      const WorkUnits& w, PlanInputs& in) const;
    static std::vector<GatherMeasurement> unmeasured_map_gathers(const PlanCandidates& candidates);
    void count_pilot_work(const PassContext& context, const std::vector<GatherMeasurement>& measured, double pilot_stored,
                          const WorkUnits& w, PlanInputs& in) const;
    void adopt_plan(const PassContext& context, const PassPlan& plan, GatherMode gather, bool uses_map, int64_t pilot_count);

    // --- photons.gather = "photon_beams" or "point_beam" under render.time_limit (beam_pilot.cpp, beam_pass_size.h):
    // the photons and samples per pass, decided once per run from two pilot maps' counted work.
    void plan_beam_pass(const PassContext& context, RunStats& stats);
    // One pilot: a map of `photons` photons on streams of its own, built, and a probe of camera samples.
    BeamPilotCounts beam_pilot(const PassContext& context, int64_t photons, uint64_t salt);
    // render.spp pinned under render.time_limit: refused or warned about where its camera pass cannot fit (auto_gather.cpp).
    void check_pinned_samples_fit(const PassContext& context, const PlanInputs& in, const GatherMeasurement& chosen,
                                  RunStats& stats) const;

    const Scene& scene_;
    PhotonMapSettings settings_;
    bool both_strategies_ = false;   // render.mis and a light a bounce can find
    MapSet maps_;
    RunDecisionMap decision_;        // the radius bound's (run_decision_map.h)
    PassEstimators pass_;            // this pass's k and estimators (photons.schedule); the plan measures pass 0's apart
    // A segment gather in force (photons.gather = "point_beam", "photon_beams"): this pass's structure.
    std::unique_ptr<SegmentGather> segment_gather_;
    GatherChoice choice_;
    PhotonAccounts photons_;
    PassRadiiStats radii_log_;       // the sidecar's photons.radii.* (render/run/run_stats.h)
    std::unique_ptr<ThreadState> threads_;
    PathTracer continuation_;        // the camera paths once the plan chose "continue"
};

// Operations the counters hold, over all threads (render/plan/pass_plan.h's cost model).
CountedOperations counted_operations(const CounterSet& counters);

// The registry's readers: [photons] and the walk keys of [render], for "photon_map" and for "auto"
// (the same keys; chooses_integrator set, and photons.gather checked against it where it is chosen).
std::unique_ptr<IntegratorSettings> read_photon_map_settings(Params& render, Params& root);
std::unique_ptr<IntegratorSettings> read_auto_integrator_settings(Params& render, Params& root);

// A config's photon-map settings (read whichever integrator it chose).
const PhotonMapSettings& photon_map_settings(const RunConfig& config);

}  // namespace vpm
