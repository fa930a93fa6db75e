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
#include "render/plan/pass_plan.h"
#include "render/path/path_tracer.h"
#include "render/photon_map/photon_pass.h"
#include "render/photon_map/camera_path.h"
#include "render/photon_map/volume_estimate.h"
#include "render/run/run_config.h"
#include "transport/mis.h"
#include "render/run/run_stats.h"
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
    std::string integrator_used() const { return no_map_ ? "path" : "photon_map"; }
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
    bool stateless_passes() const override { return no_map_; }
    double one_off_seconds() const override { return one_off_seconds_; }
    // The gather in force: photons.gather, or what "auto" or "pilot" chose; "march" for a pass whose
    // segment gather had nothing to query.
    GatherMode gather() const { return gather_; }
    const std::optional<GatherPilotStats>& gather_pilot() const { return pilot_; }
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
    const Scene& scene_;
    PhotonMapSettings settings_;
    bool owns_maps_;
    PhotonMaps owned_;
    std::optional<LightAllocation> allocation_;   // photons per light, from the run's first pass
    const PhotonMap* map_;
    const PhotonMap* surface_map_;
    // Glass interfaces (scene/dielectric_regions.h): the maps per region, null in a scene without
    // closed glass shapes; the camera paths' estimates take their own region's (camera_path.h).
    const RegionPhotonMaps* volume_regions_ = nullptr;
    const RegionPhotonMaps* surface_regions_ = nullptr;
    // The bound's decision map (photon/estimate/bounded_radius.h): traced once per run with a seed of its own
    // at photons.count / kDecisionMapShare photons, so every pass and machine of a run decides alike.
    // decision_ratio_ = emitted photons of map_ / of the decision map. (At photons.count it cost the
    // dense box of optical side 100 a second, as much as the pass's own photon pass: docs/studies/
    // heldout_scenes.md, section 31.)
    static constexpr int64_t kDecisionMapShare = 8;
    PhotonMap decision_owned_;
    const PhotonMap* decision_map_ = nullptr;
    PhotonCellCounts decision_cells_;   // answers most decisions in thin media without a query
    double decision_ratio_ = 1.0;
    double decision_emitted_ = 0.0;   // the decision map's emitted photons (owned)
    double map_emitted_ = 0.0;        // map_'s emitted photons (owned maps)
    // Whether passes trace a surface photon map: surfaces, and final_gather off.
    bool traces_surface_map() const;
    // Whether this run's estimates need a decision map: media, the bound on, a gather that uses it.
    bool wants_decision_map() const;
    // Traces decision_owned_ (once per run) and logs it.
    void trace_decision_map(const PassContext& context, RunStats& stats);
    // decision_ratio_ for a volume map of `emitted` photons.
    void set_map_emitted(double emitted);
    double max_radius_;
    size_t k_;   // this pass's k (photons.schedule)
    // This pass's estimators with their radius scales, and the beam discs' (photons.schedule;
    // render/photon_map/photon_map_settings.h: radii_for_pass).
    Estimator volume_estimator_, surface_estimator_;
    double beam_scale_ = 1.0;
    PassRadiiStats radii_log_;   // the sidecar's photons.radii.* (render/run/run_stats.h)
    void schedule_pass(int pass);
    bool warned_k_ = false;   // "k exceeds the stored count" is logged once per run
    std::unique_ptr<ThreadState> threads_;
    // A segment gather in force (photons.gather = "point_beam", "photon_beams"): this pass's structure.
    std::unique_ptr<SegmentGather> segment_gather_;
    // Builds it over this pass's maps (logging and timing the build when given); an unusable one
    // (nothing to query) leaves the pass gathering like "march".
    void build_segment_gather(std::ostream* log, RunStats* stats);
    // Adds its counts to the run's statistics and frees it.
    void retire_segment_gather(RunStats& stats);
    // This pass's photon maps with `count` photons (the last pass's freed first).
    void trace_maps(const PassContext& context, int64_t count, bool surface, RunStats& stats);
    // The photons of the run's first map (and of the auto plan's pilot map): photons.count, or fewer
    // where an auto plan sizes the count and walks store many photons each (render/photon_map/photon_pass.h).
    // Decided once per run, on a probe with the run's streams, so every pass range plans alike.
    int64_t first_map_photons(const PassContext& context, RunStats& stats);
    void check_pinned_count_fits(const PassContext& context, RunStats& stats);
    int64_t first_map_photons_ = 0;   // 0: not decided yet
    double one_off_seconds_ = 0.0;    // one_off_seconds(): the probe, the pilot, its map when traced again, the decision map
    double last_trace_seconds_ = 0.0; // trace_maps' last photon pass
    PhotonLedger ledger_;             // photons traced per phase (RunStats::photon_ledger)

    // This pass's maps as the camera path reads them, with `gather` in force over `volume` and `surface`
    // (the pass's own, or a pilot's candidates); decision_ratio: the decision map's (decision_ratio_for).
    PassMaps pass_maps(GatherMode gather, const PhotonMap& volume, const PhotonMap* surface, double decision_ratio) const;
    // The decision ratio for a volume map of `emitted` photons.
    double decision_ratio_for(double emitted) const;
    bool both_strategies_ = false;   // render.mis and a light a bounce can find
    // Whether the volume map is too small for any estimate (the warning in prepare()).
    bool volume_map_starved() const;

    GatherMode gather_ = GatherMode::collision;
    std::optional<GatherPilotStats> pilot_;
    // gather = "pilot": renders a pilot (8 x 8 camera rays spread over the image, 16 samples each,
    // streams of their own) with each candidate and keeps the one with the least variance x cost,
    // the cost from deterministic counts (kNN queries, rays, ball-quadrature lookups). Same choice
    // on any machine, thread count and scale.
    void choose_gather(const PassContext& context);

    // gather = "auto" (render/photon_map/auto_gather.cpp): on the run's first pass, the map-noise pilot
    // (render/plan/map_noise_pilot.h) measures collision and march, and the plan (render/plan/pass_plan.h)
    // picks the gather, and under render.time_limit the photons and samples per pass.
    std::optional<PassPlan> plan_;
    std::optional<AutoGatherStats> auto_stats_;
    // The plan chose "continue" (render/plan/no_map_candidate.h): no photon pass, and the camera paths
    // are the path tracer's. With an empty map trace() draws the same paths in distribution, but
    // pays for the map's bookkeeping at every collision: 1.2-1.5x the path tracer's time per sample.
    bool no_map_ = false;
    PathTracer continuation_;
    PhotonMap empty_map_;   // the "continue" candidate's map in the pilot
    void plan_auto(const PassContext& context, RunStats& stats);

    // photons.gather = "photon_beams" under render.time_limit (render/photon_map/beam_pass_size.h):
    // the photons and samples per pass, decided once per run from two pilot maps' counted work.
    std::optional<BeamPassSize> beam_pass_;
    void plan_beam_pass(const PassContext& context, RunStats& stats);
    // One pilot: a map of `photons` photons on streams of its own, built, and a probe of camera samples.
    BeamPilotCounts beam_pilot(const PassContext& context, int64_t photons, uint64_t salt);
    void warn_if_pinned_samples_overrun(const PassContext& context, const PlanInputs& in, const GatherMeasurement& chosen,
                                        RunStats& stats) const;
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
