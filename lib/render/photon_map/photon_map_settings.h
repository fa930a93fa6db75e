#pragma once
// The photon-map integrator's settings: its [photons] table and the walk keys of [render].
//
//   | key                    | default     | meaning                                                  |
//   |------------------------|-------------|----------------------------------------------------------|
//   | count                  | 100000      | photons emitted                                          |
//   | k                      | 32          | nearest neighbours per estimate (>= the estimator's min) |
//   | estimator              | "corrected" | a name from the estimator registry (photon/estimate/estimators.h) |
//   | kernel                 | "constant"  | a name from the kernel registry (photon/estimate/kernels.h): the  |
//   |                        |             | estimator above with this kernel (volume 3D, surface 2D) |
//   | cone_slope             | 1           | kernel "cone" only: K = 1 - s t, s in (0, 1]             |
//   | direct                 | "nee"       | "nee": single scattering by NEE, the map holds the rest;  |
//   |                        |             | "photon_map": everything from the map (the bias study)   |
//   | max_radius             | 0           | kNN search radius; 0: unbounded                          |
//   | max_bounces            | 1000        | collisions + bounces per photon path (truncation)        |
//   | memory_budget_fraction | 0.5         | warn when the map would take more of physical memory     |
//   | final_gather           | false       | true: no surface map, camera paths bounce off surfaces   |
//   | forced_collisions      | false       | true: photons collide in every medium segment, power     |
//   |                        |             | times 1 - exp(-tau) (photon/trace/forced_collision.h)          |
//   | extinction             | "linear"    | "ball": mean sigma_t over the kNN ball; "point": at x;   |
//   |                        |             | "linear": the ball's, exact for linear radiance across   |
//   |                        |             | it (photon/estimate/linear_estimate.h; docs/dense_bias.md, fourth |
//   |                        |             | session: the default's measurement)                      |
//   | max_radius_mfp         | 2           | kNN radius <= this many mean free paths at the query;    |
//   |                        |             | fewer than k photons within: the camera path continues   |
//   |                        |             | (photon/estimate/bounded_radius.h: decided on the run's decision  |
//   |                        |             | map, count / 8 photons of a seed of its own); 0: off     |
//   | allocation             | "importance"| photons per light: "importance" (pilot: power landing    |
//   |                        |             | where the camera looks) | "power" (photon_allocation.h)  |
//   | gather                 | "auto"      | camera side: "collision": one estimate where the camera  |
//   |                        |             | ray collides; "march": up to gather_queries stratified   |
//   |                        |             | points (march_points) along every segment in the media   |
//   |                        |             | (the free flight of the medium's exact extinction:       |
//   |                        |             | transport/march_points.h),                               |
//   |                        |             | each weighing albedo (1 - T) / n times the other media's |
//   |                        |             | transmittance (every ray gathers, also in thin media);   |
//   |                        |             | a point whose ball exceeds max_radius_mfp takes NEE and  |
//   |                        |             | a continued path (counted: photons.march_wide_queries).  |
//   |                        |             | "auto": the run's first pass measures collision and march|
//   |                        |             | (per-sample and photon-map variance, counted work) and   |
//   |                        |             | keeps the least error^2 x work; under render.time_limit  |
//   |                        |             | it also sizes photons and samples per pass unless count  |
//   |                        |             | or render.passes is given (pass_plan.h, map_noise_pilot.h)|
//   |                        |             | "threshold": per camera segment, "march" where the media's|
//   |                        |             | majorant optical depth along it is at most               |
//   |                        |             | march_max_optical_depth, else "collision" (chosen from   |
//   |                        |             | geometry alone, so the mixture stays unbiased).          |
//   |                        |             | "pilot": each pass renders a pilot with collision, march |
//   |                        |             | and auto and keeps the least variance x cost, the cost   |
//   |                        |             | from counted work (queries, rays, lookups), not the      |
//   |                        |             | clock (photon_map_integrator.h: choose_gather). Opt-in:  |
//   |                        |             | its per-sample variance misses the photon map's own      |
//   |                        |             | noise (docs/studies/auto_plan.md section 11.2)                       |
//   |                        |             | "point_beam": the beam radiance estimate, one query per  |
//   |                        |             | segment over a BVH of the photons' discs                 |
//   |                        |             | (render/photon_map/beam_gather.h), single scattering by  |
//   |                        |             | NEE at gather_queries points per segment. "beam" is its  |
//   |                        |             | old name, still accepted (a note on stderr says so).     |
//   |                        |             | "photon_beams": the photon paths' free flights as beams, |
//   |                        |             | the 1D beam x beam estimate with kNN widths              |
//   |                        |             | (render/photon_map/photon_beam_gather.h,                 |
//   |                        |             | docs/photon_beams.md); single scattering by NEE as above |
//   | gather_queries         | 4           | points per segment for "march" (NEE points for "beam")   |
//   | march_points           | "mass"      | "march": how many points a crossed medium gets: "mass"   |
//   |                        |             | ceil(gather_queries (1 - T)), at least 1; "fixed"        |
//   |                        |             | gather_queries; "free_flight" gather_queries stratified  |
//   |                        |             | free flights, those inside the segment                   |
//   |                        |             | (transport/march_count.h; docs/studies/march.md section 18)      |
//   | beam_k                 | 32          | "point_beam": each photon's radius is its beam_k-th      |
//   |                        |             | nearest other photon (photon/map/photon_radii.h)         |
//   | beam_widths            | "balloon"   | "photon_beams": "balloon" (the width at the camera       |
//   |                        |             | segment from its k-th nearest beam, estimator classic or |
//   |                        |             | corrected) | "sample_point" (each beam's width from its  |
//   |                        |             | own k-th nearest other beam). k is photons.k (per pass:  |
//   |                        |             | photons.schedule), the kernel photons.kernel in 1D, the  |
//   |                        |             | width bounded by max_radius                              |
//   | clustering             | "ignore"    | "leave_group_out" (corrected, constant kernel, ball or   |
//   |                        |             | linear extinction, even k; else refused): each half of   |
//   |                        |             | the walk groups counted within the (k/2)-th photon of    |
//   |                        |             | the other half ("shrink" rounds a pass's k up to even),  |
//   |                        |             | exact for clustered walks                                |
//   |                        |             | (photon/estimate/group_estimate.h)                       |
//   | store_probability      | 1           | each volume collision stored with this probability and   |
//   |                        |             | its power divided by it (thinning; photon_tracer.h);     |
//   |                        |             | "auto": min(1, 2 / stored per storing walk of the pass's |
//   |                        |             | first 4096 photons) for the rest (store_thinning.h)      |
//   | march_max_optical_depth| 2           | the "threshold" gather's threshold                       |
//   | sampler                | "independent" | photon paths: "independent", "stratified" (per batch)   |
//   |                        |             | or "sobol" (over the pass; count < 2^32): core/sampler.h |
//   | schedule               | "fixed"     | radii across passes (docs/progressive.md). "fixed": k and |
//   |                        |             | the k-th neighbour's ball in every pass; "progressive":  |
//   |                        |             | Knaus & Zwicker's measure ratio (i + alpha)/(i + 1) per  |
//   |                        |             | pass, by pass index (render.first_pass counts): k shrinks|
//   |                        |             | to k_floor, the radius s r_k below it, each estimate     |
//   |                        |             | exact on a uniform density (photon/estimate/             |
//   |                        |             | radius_schedule.h); points, surfaces and "beam" alike;   |
//   |                        |             | "shrink": k_i = max(k_floor, round(k i^(alpha-1))), 1-   |
//   |                        |             | based i, no radius scale: its bias stops at k_floor      |
//   | alpha                  | "auto"      | in (0, 1]: the schedule's rate for every estimate; "auto":|
//   |                        |             | 4/(d+4) per kernel dimension d (4/7 points, 2/3 surfaces |
//   |                        |             | and "beam"), 2/3 for "shrink"                             |
//   | k_floor                | 4           | smallest k of the schedule (>= the estimator's min + 1)   |
#include <cstdint>

#include "core/math.h"
#include "core/sampler.h"
#include "photon/estimate/estimators.h"
#include "transport/march_count.h"
#include "transport/walk_settings.h"

namespace vpm {

class Params;

enum class DirectLighting { nee, photon_map };
enum class ExtinctionNormalisation { ball, point, linear };
enum class Clustering { ignore, leave_group_out };
enum class PhotonAllocationRule { importance, power };
enum class GatherMode { collision, march, automatic, pilot, threshold, beam, photon_beams };
enum class BeamWidths;   // render/photon_map/photon_beam_gather.h
enum class KSchedule { fixed, shrink, progressive };

// One pass's k and radius scales (photons.schedule; photon/estimate/radius_schedule.h).
struct PassRadii {
    int k = 32;
    double volume_scale = 1.0, surface_scale = 1.0, beam_scale = 1.0;
};

struct PhotonMapSettings {
    int64_t count = 100000;
    bool count_given = false;   // photons.count was set (else count is its default)
    int k = 32;
    Estimator estimator = Estimator::named("corrected");   // carries the kernel (photons.kernel)
    DirectLighting direct = DirectLighting::nee;
    double max_radius = 0.0;
    int max_bounces = 1000;
    double memory_budget_fraction = 0.5;
    bool final_gather = false;
    bool forced_collisions = false;   // photon/trace/forced_collision.h
    ExtinctionNormalisation extinction = ExtinctionNormalisation::linear;
    double max_radius_mfp = 2.0;
    PhotonAllocationRule allocation = PhotonAllocationRule::importance;
    GatherMode gather = GatherMode::automatic;
    int gather_queries = 4;
    MarchCount march_points = MarchCount::mass;   // points per crossed medium (transport/march_points.h)
    int beam_k = 32;
    BeamWidths beam_widths{};   // "balloon" (0)
    double store_probability = 1.0;
    SamplerKind sampler = SamplerKind::independent;   // photons.sampler
    bool store_auto = false;   // store_probability = "auto": from the pass's walk statistics (photon/trace/store_thinning.h)
    Clustering clustering = Clustering::ignore;
    double march_max_optical_depth = 2.0;
    KSchedule schedule = KSchedule::fixed;
    // render.integrator = "auto": the plan may render the run with the path tracer instead of the
    // map (render/plan/no_map_candidate.h). "photon_map" (false) always estimates from its maps.
    bool chooses_integrator = false;
    // A plan (gather = "auto", "collision" or "march", or the "auto" integrator) with render.time_limit > 0 sizes the photons
    // per pass unless photons.count is given, the samples per pass unless render.spp or
    // render.passes is.
    bool size_photons = false, size_samples = false;
    bool passes_given = false;   // render.passes set (under a limit it pins the pass, the path tracer's too)
    double time_limit = 0.0;   // render.time_limit (the plan's budget)
    double alpha = 0.0;   // 0: "auto" (alpha_for)
    int k_floor = 4;
    WalkSettings walk;

    // k of pass `pass_index` (0-based, counting from render.first_pass) under the schedule
    // (the volume estimate's; radii_for_pass for all of a pass).
    int k_for_pass(int pass_index) const;
    // photons.clustering = "leave_group_out" applies: the corrected estimator, constant kernel,
    // ball or linear extinction (from_params refuses it elsewhere, and an odd k).
    bool leaves_group_out() const;
    // The schedule's alpha for a kernel of dimension dim: photons.alpha, or "auto"'s.
    double alpha_for(int dim) const;
    // Pass `pass_index`'s k and radius scales; volume, surface: the maps the run queries (the k serves both).
    PassRadii radii_for_pass(int pass_index, bool volume, bool surface) const;
    // The kNN search radius: kInfinity when unbounded.
    double search_radius() const { return max_radius > 0 ? max_radius : kInfinity; }
    // Whether a time limit's plan may size this run's passes: the gathers the pilot measures
    // ("auto", "collision", "march") or the "auto" integrator.
    bool plan_sizes_passes() const {
        return gather == GatherMode::automatic || gather == GatherMode::collision || gather == GatherMode::march ||
               chooses_integrator;
    }
    // Whether a plan runs on the first pass (render/plan/pass_plan.h): gather = "auto", the "auto"
    // integrator, or a collision or march gather whose passes a time limit sizes.
    bool plans() const { return gather == GatherMode::automatic || chooses_integrator || size_photons || size_samples; }
    // Reads [photons] and the walk keys of [render]; throws ConfigError (k below the estimator's
    // minimum names both keys) and warns on stderr about corrected with k = 2 (not for the "auto"
    // integrator's reading of the same table: chooses_integrator).
    static PhotonMapSettings read(Params& render, Params& photons, bool chooses_integrator = false);
};

}  // namespace vpm
