#pragma once
// The photon-map renderer (integrator = "photon_map").
//
// A camera path is traced exactly like the reference path tracer until its first real collision
// in a medium (delta tracking: the collision estimator, so the line integral adds no bias).
// There the in-scattered radiance is taken from the volume photon map and the path ends:
//
//     L += throughput * albedo(x) * S(x, w_o) / sigma_t(x)
//
// S is the kNN estimate of the collision-weighted in-scattering density (photons are stored at
// every real collision, so S estimates sigma_t * integral f L dw); dividing by sigma_t(x) undoes
// the collision pdf. With direct = "nee", single scattering is added by next-event estimation and
// the map holds only photons that scattered before (photon tracer's store_direct = false).
// Surfaces on the way get direct light by NEE and continue the path with a diffuse bounce, so
// light reaching the medium via walls is found at the next medium collision. The estimator's
// bias is then the only bias in the image.
//
// photons.extinction = "ball" (the default) divides by the mean sigma_t over the kNN ball (closed
// forms where a medium has one, else a 15-point degree-5 rule: photon/estimate/ball_extinction.h) instead of sigma_t(x). S averages sigma_t L over that ball, so
// the ratio is consistent like the point version and identical inside a homogeneous medium, but it
// does not blow up where a ball reaches from a thin plume edge (sigma_t(x) ~ 0) into dense smoke, and
// it cancels the part of the ball that lies outside the medium (boundary bias). The line integral
// is still the collision estimator; "point" is docs/design.md's formula. Measured on the default scene
// (256x256, 1e6 photons, corrected, relative RMSE against a 1024-spp path-traced reference):
// k = 8: 0.161 point / 0.124 ball, k = 32: 0.216 / 0.091; bias +0.013 / +0.004 at k = 32.
// "linear" divides the same way and weighs each photon so that a radiance linear across
// the ball is exact (photon/estimate/linear_estimate.h).
//
// With a surface photon map (photons.final_gather = false, the default, in a scene with shapes)
// the camera path ends at its first surface hit instead:
//
//     L += throughput * (direct by NEE + reflectance / pi * E(x))        direct = "nee"
//     L += throughput * reflectance / pi * E(x)                          direct = "photon_map"
//
// E is the surface map's kNN irradiance estimate (estimate_surface_irradiance, pi r_k^2, same
// estimator and k as the volume map). With "nee" the surface map holds only photons that scattered
// before (off a medium or a surface), with "photon_map" every hit, as for the volume map.
// Without a surface map (final_gather = true) surfaces behave as described above.
//
// k above the stored count: a map holding fewer than k photons, an empty one included,
// is never queried, at a collision, a march point or a surface hit. No ball there can hold k
// photons, so the camera path continues past the point like the path tracer's (unbiased), instead
// of estimator rule (b)'s whole-map estimate, which costs a pass over the map per query (k = 65536
// over 55,265 photons: minutes for a 48x48 image). prepare() logs a warning once per run.
//
// Emission: the camera sees area lights and the sky directly. After a final-gather bounce or a
// path continued in a medium (max_radius_mfp, a starved map, "continue"), NEE and the bounce are
// MIS-weighted like the path tracer's (render.mis, transport/mis.h); where the map ends the path,
// single scattering takes both strategies (transport/single_scattering.h).
#include <functional>
#include <memory>
#include <optional>

#include "photon/estimate/bounded_radius.h"
#include "photon/estimate/estimators.h"
#include "photon/map/photon_cell_counts.h"
#include "photon/map/photon_map.h"
#include "render/integrator.h"
#include "render/photon_map/photon_map_settings.h"
#include "render/plan/pass_plan.h"
#include "render/path/path_tracer.h"
#include "render/photon_map/beam_gather_stats.h"
#include "render/photon_map/photon_beam_gather_stats.h"
#include "render/photon_map/photon_pass.h"
#include "render/run/run_config.h"
#include "transport/mis.h"
#include "render/run/run_stats.h"
#include "scene/scene.h"

namespace vpm {

class BeamGather;
class PhotonBeamGather;
struct SegmentPoint;

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
    // The gather in force, by its name ("collision", "march", "threshold", "beam"); "none" without a map.
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
    // The gather in force: photons.gather, or for "pilot" what this pass's pilot chose.
    // threshold ("auto"): per segment, the march where its majorant optical depth <= march_max_optical_depth.
    // beam: one BVH query per segment (render/photon_map/beam_gather.h); a map without discs falls back to march.
    // photon_beams: one BVH query of the photon beams per segment (render/photon_map/photon_beam_gather.h).
    enum class Gather { collision, march, threshold, beam, photon_beams };
    Gather gather() const { return gather_; }
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
    // closed glass shapes. A camera path tracks its region (ThreadState::Local::region) as photons do, and its
    // estimates count only the photons of that region, over the share of the ball inside it.
    const RegionPhotonMaps* volume_regions_ = nullptr;
    const RegionPhotonMaps* surface_regions_ = nullptr;
    const PhotonMap& volume_map_here() const;
    const PhotonMap* surface_map_here() const;
    double region_share(const Vec3& x, double radius) const;
    // The bound's decision map (photon/estimate/bounded_radius.h): traced once per run with a seed of its own
    // at photons.count / kDecisionMapShare photons, so every pass and machine of a run decides alike.
    // decision_ratio_ = emitted photons of map_ / of the decision map. (At photons.count it cost the
    // dense box of optical side 100 a second, as much as the pass's own photon pass: docs/studies/
    // heldout_scenes.md, section 31.)
    static constexpr int64_t kDecisionMapShare = 8;
    static constexpr size_t kDecisionMinK = 4;
    PhotonMap decision_owned_;
    const PhotonMap* decision_map_ = nullptr;
    PhotonCellCounts decision_cells_;   // answers most decisions in thin media without a query
    double decision_ratio_ = 1.0;
    struct DecisionBall {
        size_t k = 0;        // photons of the decision map that must lie within
        double radius = 0;   // this radius
    };
    // The decision map's test equivalent to "k photons of map_ within `radius`".
    DecisionBall decision_ball(double radius) const;
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
    std::unique_ptr<BeamGather> beam_;   // gather = "beam": this pass's radii and disc BVH
    BeamGatherStats beam_before_;        // earlier passes' beam counts and build times
    // gather = "beam": builds beam_ over map_ (or falls back to collision) and logs it.
    void build_beam(std::ostream* log, RunStats* stats);
    // Frees beam_, keeping its counts in beam_before_.
    void retire_beam();
    std::unique_ptr<PhotonBeamGather> photon_beams_;   // gather = "photon_beams": this pass's beams and BVH
    PhotonBeamGatherStats photon_beams_before_;        // earlier passes' counts and build times
    // gather = "photon_beams": builds photon_beams_ from this pass's beams (owned_.beams) and logs it.
    void build_photon_beams(std::ostream* log, RunStats* stats);
    void retire_photon_beams();
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
    // gather = "beam": the segment's in-scattering, single scattering by NEE when direct = "nee".
    Rgb beam_in_scattering(const Ray& ray, double t_end, Rng& rng) const;

    // The camera path's radiance from `ray` on, after `first_depth` scattering events; emission it
    // meets first counts as `first_emission` says.
    Rgb trace(const Ray& ray, int first_depth, Rng& rng, const EmissionWeighting& first_emission = EmissionWeighting::camera()) const;
    // Single scattering at a medium vertex (transport/single_scattering.h): `goes_on`, the path continues
    // past x (MIS-weighted NEE when render.mis); else the map ends it (both strategies where they apply).
    // `at`: x's segment also samples point and spot lights equiangularly (transport/equiangular.h).
    Rgb single_scattering(const Vec3& x, const Vec3& dir, double g, bool goes_on, Rng& rng,
                          const SegmentPoint* at = nullptr) const;
    bool both_strategies_ = false;   // render.mis and a light a bounce can find
    // gather = "march": the in-scattered radiance along `ray` over the media inside (0, t_end),
    // from gather_queries stratified points, each weighted by a ratio-tracked transmittance.
    // A point whose kNN ball is wider than max_radius_mfp mean free paths gets NEE and a continued
    // path (scattering event number depth + 1) instead of its biased estimate.
    // depth: as for_each_march_point's (transport/march_points.h), when non-null.
    Rgb march_in_scattering(const Ray& ray, double t_end, int depth, Rng& rng, double* optical_depth = nullptr) const;
    // The volume estimate s at x (gathered into buffers) divided by sigma_t as photons.extinction says.
    // w_o, g, max_radius: the query's, for the leave-group-out gather (photons.clustering).
    // photons.clustering = "leave_group_out" applies (corrected, constant kernel, ball or linear), and
    // the kNN list to gather for it (photon/estimate/group_estimate.h); else k.
    bool leaves_half_out() const;
    size_t gather_count() const;
    Rgb normalised(const Estimate<Rgb>& s, const Vec3& x, const Vec3& w_o, double g, double max_radius, double sigma_t,
                   GatherBuffers& buffers, std::vector<Rgb>& scratch) const;
    // The phase-weighted incident radiance at march point x (weight: the point's, for roulette).
    Rgb incident_at_march_point(const Vec3& x, const Vec3& dir, double g, double sigma_t, const Rgb& weight,
                                int depth, Rng& rng, const SegmentPoint* at = nullptr) const;
    // Whether the volume map is too small for any estimate (photon/estimate/bounded_radius.h): then every
    // query, at a collision or a march point, continues the path instead.
    bool volume_map_starved() const;
    // The volume estimate at x (sigma_t > 0 there) and what photon/estimate/bounded_radius.h's rule makes of
    // it: decided on the decision map where there is one (then the estimate's ball is unbounded),
    // else on the estimate's own list gathered within photons.max_radius_mfp mean free paths. The one
    // query and rule of the collision gather and the march alike. (The march once switched on r_k
    // alone, without the rule's zero at k - 1 photons, and read up to 7% high near the bound:
    // docs/studies/heldout_scenes.md section 30.)
    struct BoundedEstimate {
        Estimate<Rgb> estimate;
        double radius = 0.0;                           // the ball's bound: max_radius_ or the mean-free-path one
        BoundedQuery rule = BoundedQuery::use_estimate;
    };
    BoundedEstimate bounded_in_scattering(const Vec3& x, const Vec3& w_o, double g, double sigma_t, GatherBuffers& buffers,
                                          EstimatorStats* stats) const;
    // Whether the camera segment `ray` up to t_end gathers by the march (gather_, below).
    bool marches(const Ray& ray, double t_end) const;

    Gather gather_ = Gather::collision;
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
    void warn_if_pinned_samples_overrun(const PassContext& context, const PlanInputs& in, const GatherMeasurement& chosen,
                                        RunStats& stats) const;
    // Runs f with fresh per-thread counters and buffers, so that a pilot's work is not the run's.
    void with_fresh_counters(const std::function<void()>& f);
    // Operations counted so far over all threads (render/plan/pass_plan.h).
    CountedOperations counted_operations() const;
};

// The registry's readers: [photons] and the walk keys of [render], for "photon_map" and for "auto"
// (the same keys; chooses_integrator set, and photons.gather checked against it where it is chosen).
std::unique_ptr<IntegratorSettings> read_photon_map_settings(Params& render, Params& root);
std::unique_ptr<IntegratorSettings> read_auto_integrator_settings(Params& render, Params& root);

// A config's photon-map settings (read whichever integrator it chose).
const PhotonMapSettings& photon_map_settings(const RunConfig& config);

}  // namespace vpm
