#pragma once
// The photon-map integrator's settings: its [photons] table and the walk keys of [render], read into
// typed values. Every key with its default, allowed values and meaning: docs/config.md (the `[photons]`
// table); the gathers' names come from gathers/gather_registry.h, the estimators' and kernels' from
// their registries in photon/estimate/.
#include <cstdint>

#include "core/math.h"
#include "core/sampling/sampler.h"
#include "photon/estimate/estimators.h"
#include "photon/estimate/walk_estimate.h"
#include "render/photon_map/gathers/gather_registry.h"
#include "transport/march_count.h"
#include "transport/walk_settings.h"

namespace vpm {

class Params;

enum class DirectLighting { nee, photon_map };
// linear_signed: the linear weights with negative estimates kept (no fallback: unbiased, not non-negative).
enum class ExtinctionNormalisation { ball, point, linear, linear_signed };
enum class Clustering { ignore, leave_group_out };
enum class PhotonAllocationRule { importance, power };
enum class BeamWidths;   // render/photon_map/gathers/photon_beams_gather.h
enum class KSchedule { fixed, shrink, progressive };

// One pass's k and radius scales (photons.schedule; photon/estimate/radius_schedule.h).
struct PassRadii {
    int k = 32;
    double volume_scale = 1.0, surface_scale = 1.0, beam_scale = 1.0;
};

// One pass's k, radius bound and estimators with their radius scales, and the beam discs' scale:
// what the pass's estimates use (PhotonMapSettings::estimators_for_pass).
struct PassEstimators {
    size_t k = 32;
    double max_radius = kInfinity;
    Estimator volume, surface;
    double beam_scale = 1.0;
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
    BeamWidths beam_widths{};   // "density" (0)
    double store_probability = 1.0;
    SamplerKind sampler = SamplerKind::independent;   // photons.sampler
    bool store_auto = false;   // store_probability = "auto": from the pass's walk statistics (photon/trace/store_thinning.h)
    Clustering clustering = Clustering::ignore;
    // photons.neighbours: the kNN estimates count photons or, "walks", independent walks
    // (photon/estimate/walk_estimate.h): the volume estimate of the collision, march and threshold
    // gathers and the surface estimate.
    Neighbourhood neighbourhood = Neighbourhood::photons;
    double march_max_optical_depth = 2.0;
    // photons.glass_splits: a camera path follows both the reflection (weight F) and the refraction
    // (1 - F) at its first this many glass hits (render/photon_map/camera_path.h), each branch counting its own.
    int glass_splits = 2;
    KSchedule schedule = KSchedule::fixed;
    // render.integrator = "auto": the plan may render the run with the path tracer instead of the
    // map (render/plan/no_map_candidate.h). "photon_map" (false) always estimates from its maps.
    bool chooses_integrator = false;
    // A plan (gather = "auto", "collision" or "march", or the "auto" integrator) with render.time_limit > 0 sizes the photons
    // per pass unless photons.count is given, the samples per pass unless render.spp or
    // render.passes is.
    bool size_photons = false, size_samples = false;
    // photons.gather = "photon_beams" or "point_beam" with render.time_limit > 0: its passes are sized from counted
    // work (render/photon_map/beam_pass_size.h), the photons unless photons.count is given, the
    // samples unless render.spp or render.passes is.
    bool size_beam_photons = false, size_beam_samples = false;
    bool sizes_beam_pass() const {
        return (gather == GatherMode::photon_beams || gather == GatherMode::point_beam) && time_limit > 0.0;
    }
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
    // Pass `pass_index`'s estimators: radii_for_pass applied to photons.estimator.
    PassEstimators estimators_for_pass(int pass_index, bool volume, bool surface) const;
    // The estimators before any schedule: photons.k and photons.estimator as given.
    PassEstimators unscheduled_estimators() const { return {size_t(k), search_radius(), estimator, estimator, 1.0}; }
    // The kNN search radius: kInfinity when unbounded.
    double search_radius() const { return max_radius > 0 ? max_radius : kInfinity; }
    // Whether a time limit's plan may size this run's passes: the gathers the pilot measures
    // ("auto", "collision", "march") or the "auto" integrator.
    bool plan_sizes_passes() const {
        return gather == GatherMode::automatic || gather_entry(gather).plan_measures || chooses_integrator;
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
