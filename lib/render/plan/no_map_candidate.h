#pragma once
// The auto plan's third candidate, "continue": no photon map at all. Every medium collision then
// continues the camera path (next-event estimation and a phase-sampled bounce, as where a kNN ball
// exceeds photons.max_radius_mfp: photon/estimate/bounded_radius.h) and surfaces are path traced, so the
// estimate is unbiased and no photon pass is paid for. The pilot measures it like the gathers
// (render/plan/map_noise_pilot.h: an empty map and no surface map, one trace per sample since it has no
// map noise), the plan costs it without the photon pass (render/plan/pass_plan.h), and where it wins the
// passes after the pilot's skip the photon pass (PhotonMapIntegrator::prepare); the pilot's own pass
// renders without its map too, so the whole image is the unbiased continuation.
// Where every kNN ball is wider than max_radius_mfp (matrix v3's dense boxes, BENCHMARKS.md section
// 11.7) the map is never used: the collision gather's samples are then exactly the continuation's,
// and the photon pass (6000-21000 work units per photon) is what decides. The pilot also counts the
// estimates that used a map per sample (CountedOperations::map_used), reported in the log and sidecar.
//
// "continue" competes freely with the gathers. Until the thirteenth session it was a choice where
// its paths were long (more than 12 tracked segments per sample) only if the map was next to unused:
// in the box at optical thickness 100 and albedo 0.99 it had won the pilot on samples that missed its
// paths' heavy tail and lost the run 4.3x to the map (BENCHMARKS.md sections 11.8 and 19). That tail
// was the roulette's: survival capped at 0.95 multiplied a deep path's weight by albedo / 0.95 per
// collision (transport/walk_steps.h, cap 0.999 since). Against the path tracer with the bounded
// roulette the map took 6.5-8.8x its time to equal error there, every gather forced, and the rule
// kept the map: without it "continue" took that cell from 8.8x to 2.3x and a dense sphere (optical
// diameter 300, albedo 0.999) from 6.6x to 1.4x, and changed no plan in the other 55 matrix cells
// (BENCHMARKS.md section 32).
//
// Its pilot must see its own tail where it has one. Under a point light and a
// forward-peaked phase function (g = 0.8) most of its variance comes from paths that bounce backwards
// at their first vertex (rare under g = 0.8) and then take NEE through the forward lobe towards the
// light: samples 1000-2400x the pixel mean, one in ~10^4 (BENCHMARKS.md section 16). With 8 samples
// per pixel the pilot measured its variance 5-29x too low there and "continue" won the pilot but lost
// the run 1.4-6.9x (matrix v6). Its samples are cheap, so it takes up to kNoMapPilotSamples per pixel
// (render/plan/map_noise_pilot.h), and its variance, like every candidate's, is charged at its upper
// bound, kPlanVarianceSigmas standard errors above the pilot's figure (render/plan/pass_plan.h; the
// standard error from the samples that hold the variance, render/plan/pilot_tail.h: +2% to +14% where
// thousands to hundreds of samples hold it, +45% to +160% where twenty to one or two do). At 1024
// samples per pixel the continuation lost the g = 0.8 cells on its own score in 12 of 12 cells and
// seeds (BENCHMARKS.md section 29). Until then it was no choice where its largest 1/1024 samples held
// more than half its squared deviations; that also excluded it in a thin fog under a spot light,
// whose rare collisions in the beam are a tail of every candidate's, where it won the pilot 8-150x
// and the map lost the run 6-8x to the path tracer.
#include <algorithm>
#include <vector>

#include "render/plan/pass_plan.h"

namespace vpm {

constexpr const char* kNoMapCandidate = "continue";
constexpr double kNoMapMaxUsedShare = 0.02;

// The share of a map candidate's kNN queries whose estimate was used (0 where it made none).
inline double map_used_share(const GatherMeasurement& m) {
    return m.per_sample.queries > 0.0 ? m.per_sample.map_used / m.per_sample.queries : 0.0;
}

// A map candidate whose pilot queries almost never gave a used estimate (at most
// kNoMapMaxUsedShare of them; every kNN ball wider than max_radius_mfp) continues the path at
// nearly every collision. It is the continuation plus a photon pass that buys nothing, and its pilot
// variance is the continuation's read from fewer samples; where a no-map candidate was measured and
// is a choice, such a map candidate is not. In the box at optical thickness 1000 and albedo 0.99
// (the march's pilot: 11.7 radius-bounded searches per sample, none used) seed 1 took the march on
// 512 samples that missed the continued paths' tail, at 13x the path tracer's error^2 x time
// (BENCHMARKS.md section 28).
inline void exclude_maps_that_go_unused(std::vector<GatherMeasurement>& candidates) {
    bool no_map_choice = false;
    for (const GatherMeasurement& m : candidates) no_map_choice = no_map_choice || (!m.uses_map && !m.excluded);
    if (!no_map_choice) return;
    for (GatherMeasurement& m : candidates)
        if (m.uses_map && m.per_sample.queries > 0.0 && map_used_share(m) <= kNoMapMaxUsedShare)
            m.excluded = true;
}

}  // namespace vpm
