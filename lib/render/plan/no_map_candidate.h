#pragma once
// The auto plan's third candidate, "continue": no photon map at all. Every medium collision then
// continues the camera path (next-event estimation and a phase-sampled bounce, as where a kNN ball
// exceeds photons.max_radius_mfp: photon/estimate/bounded_radius.h) and surfaces are path traced, so the
// estimate is unbiased and no photon pass is paid for. The pilot measures it like the gathers
// (render/plan/map_noise_pilot.h: an empty map and no surface map, one trace per sample since it has no
// map noise), the plan costs it without the photon pass (render/plan/pass_plan.h), and where it wins the
// passes after the pilot's skip the photon pass (PhotonMapIntegrator::prepare); the pilot's own pass
// renders without its map too, so the whole image is the unbiased continuation.
// Where every kNN ball is wider than max_radius_mfp the map is never used: the collision gather's
// samples are then exactly the continuation's and the photon pass is what decides. The pilot counts
// the estimates that used a map per sample (CountedOperations::map_used; log and sidecar).
//
// "continue" competes freely with the gathers: a rule that kept the map where its paths were long
// rested on a roulette of unbounded variance (transport/walk_steps.h) and cost up to 8.8x the path
// tracer's time where the map lost (docs/studies/heldout_scenes.md, section 32).
//
// Its pilot must see its own tail where it has one: under a point light and g = 0.8 rare backward
// bounces carry most of its variance, so it takes up to kNoMapPilotSamples per pixel
// (render/plan/map_noise_pilot.h) and, like every candidate, is charged at its variance's upper bound,
// kPlanVarianceSigmas standard errors above the pilot's figure (render/plan/pass_plan.h, standard
// error from render/plan/pilot_tail.h). Evidence: docs/studies/auto_plan.md, section 16 and
// docs/studies/heldout_scenes.md, section 29.
#include <algorithm>
#include <vector>

#include "render/plan/pass_plan.h"
#include "scene/lights/light.h"
#include "scene/scene.h"
#include "scene/surfaces/surfaces.h"

namespace vpm {

constexpr const char* kNoMapCandidate = "continue";
constexpr double kNoMapMaxUsedShare = 0.02;

// Whether the path tracer misses light the scene has: a delta light (point, spot, direction) is
// found by next-event estimation alone, which cannot connect through a mirror or glass, so its
// light that meets one before a diffuse surface or a medium (caustics, light through a window)
// reaches no path-traced vertex. The photon map carries it. With both in the scene "continue" is
// not a candidate: decided from the scene, not from the pilot's noise, which cannot see light
// that no sample finds.
inline bool path_tracer_misses_light(const Scene& scene) {
    if (!scene.surfaces || !scene.surfaces->has_specular()) return false;
    for (const auto& light : scene.lights)
        if (light->delta()) return true;
    return false;
}

// The share of a map candidate's kNN queries whose estimate was used (0 where it made none).
inline double map_used_share(const GatherMeasurement& m) {
    return m.per_sample.queries > 0.0 ? m.per_sample.map_used / m.per_sample.queries : 0.0;
}

// A map candidate whose pilot queries almost never gave a used estimate (at most
// kNoMapMaxUsedShare of them; every kNN ball wider than max_radius_mfp) continues the path at
// nearly every collision. It is the continuation plus a photon pass that buys nothing, and its pilot
// variance is the continuation's read from fewer samples; where a no-map candidate was measured and
// is a choice, such a map candidate is not (a march whose pilot used no estimate was chosen on
// samples that missed the continued paths' tail: docs/studies/auto_plan.md, section 28).
inline void exclude_maps_that_go_unused(std::vector<GatherMeasurement>& candidates) {
    bool no_map_choice = false;
    for (const GatherMeasurement& m : candidates) no_map_choice = no_map_choice || (!m.uses_map && !m.excluded);
    if (!no_map_choice) return;
    for (GatherMeasurement& m : candidates)
        if (m.uses_map && m.per_sample.queries > 0.0 && map_used_share(m) <= kNoMapMaxUsedShare)
            m.excluded = true;
}

}  // namespace vpm
