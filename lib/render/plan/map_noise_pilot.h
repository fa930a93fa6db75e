#pragma once
// The pilot behind photons.gather = "auto": for each candidate gather, at a grid of pilot pixels,
// camera samples traced with the pass's photon map and with its two independent halves (photon/
// walk_group_split.h), every map with the same random numbers per sample. From them, per candidate (render/plan/pass_plan.h):
//   V_camera  the per-sample variance at a pixel with the full map (within a pass),
//   V_map     the variance of a pixel's mean from the map alone, at N0/2 from the two halves:
//             E[(mean_A - mean_B)^2] = 2 V_map(N0/2) + Var(A - B) / n (the samples' own share of
//             the difference, measured per pixel and subtracted),
//   bias^2    the squared bias of a pixel at N0, from the half maps' mean minus the full map's
//             (the same samples: the difference is the maps' alone), pooled with its sign over the
//             pixels and charged only where resolved (render/plan/pilot_bias.h),
//   cost      counted work units per sample with the full map (queries, rays, lookups).
// The variances and the bias are relative: each pixel's weighted by 1 / (R^2 + 0.01), R its mean over
// the candidates' samples (render/plan/relative_error.h), so the plan minimises the relMSE per pixel.
// A per-sample variance alone misses V_map: every sample of a pass sees the same map. Pixels,
// samples and streams are fixed by the seed, so the figures are the same on any thread count.
// Each pilot pixel's samples jitter within that one pixel: spread over a block of the image, their
// variance would count the image's own variation as noise (the "pilot" gather's error: it made the
// march's variance look 10x larger in the box at optical thickness 1, docs/studies/auto_plan.md section 11.7).
// V_camera and V_map are also measured at the centres of a 16 x 16 grid, 2 samples each with the
// full map and its halves (a map candidate's cost per sample is its 8 x 8 pixels'): on a sphere lit
// from the side the 8 x 8 centres missed its lit rim, 1% of the pixels with 75% of the march's
// camera noise, and read 1/7 of it; in a thin plume under a sun (bench/heldout/h16) a tenth of them
// held the map's noise, and V_map read from them alone ranged over 0.18-2.8x its mean over seeds
// (docs/studies/heldout_scenes.md section 30). A pilot of 16 x 16 pixels at 8 samples for every figure instead was
// worse in 8 of 11 matrix cells at a 2 s budget (fewer samples per pixel; section 23).
// Quarter maps (V_map at N0/4, hence the exponent beta) doubled the pilot's cost and changed no
// plan in the matrix cells tried (the map's share was below the camera's in all of them): not traced.
#include <functional>
#include <string>
#include <vector>

#include "photon/map/photon_map.h"
#include "core/sampling/rng.h"
#include "render/plan/pass_plan.h"
#include "render/plan/pilot_budget.h"
#include "scene/camera.h"

namespace vpm {

struct MapNoisePilotHooks {
    // Puts candidate c's gather and `map` in force for the following traces (called between
    // parallel loops, never during one).
    std::function<void(int candidate, const PhotonMap* map)> use;
    std::function<Rgb(const Ray&, Rng&)> trace;   // one camera sample, thread-safe
    std::function<CountedOperations()> counts;    // operations counted so far, over all threads
    std::function<double(const CountedOperations&)> work;   // their work units
    // Whether a camera ray meets a surface or a medium (render/plan/pilot_pixels.h); unset: the pilot's
    // pixels are the block centres, as if every pixel did.
    std::function<bool(const Ray&)> sees;
    // Called on the candidate without a map between its stages (kNoMapStopFirstStage samples per
    // pilot pixel, doubling) with every candidate's figures so far, itself last: whether its pilot
    // stops there (render/plan/no_map_stop.h); it may set the last one's stop_ figures. Unset: never.
    std::function<bool(std::vector<GatherMeasurement>& so_far)> stop;
};

constexpr int kPilotSide = 8;       // pilot pixels: the centres of an 8 x 8 grid of image blocks
constexpr int kPilotSamples = 8;    // samples per pilot pixel and map, at most (render/plan/pilot_budget.h)
// The second grid (above): its centres, kPilotSpreadSamples each with the full map and (where traced)
// its halves, for a candidate that may use the map and was not dropped (outside the budget share:
// as many traces again as its 8 x 8 pixels' at kPilotSamples).
constexpr int kPilotSpreadSide = 16;
constexpr int kPilotSpreadSamples = 2;
// A candidate without a map takes up to this many samples per pilot pixel: within its budget share,
// or without a budget no more counted work than the candidates before it spent (render/plan/no_map_candidate.h:
// its variance sits in a tail that 8 samples per pixel do not reach).
constexpr int kNoMapPilotSamples = 1024;
constexpr int kNoMapStopFirstStage = kPilotSamples;
// The largest samples whose share of the variance the pilot reports (render/plan/pilot_tail.h).
constexpr double kPilotTailFraction = 1.0 / 1024.0;

struct PilotCandidate {
    std::string name;
    bool uses_map = true;   // false: traced once per sample (no halves): V_map and bias^2 are 0
};

// `candidates` in the order `use` takes them (v_map_quarter is left -1). Under a budget
// (render/plan/pilot_budget.h) each takes the samples its share pays for, and one whose one-sample pass
// over `image_pixels` exceeds budget.max_pass_cost stops after its probe (dropped) once an earlier
// candidate fitted.
std::vector<GatherMeasurement> measure_gathers(const Camera& camera, const PhotonMap& map,
                                               const std::vector<PilotCandidate>& candidates,
                                               MapNoisePilotHooks& hooks, uint64_t seed, uint64_t stream,
                                               const PilotBudget& budget = {}, double image_pixels = 0.0);

}  // namespace vpm
