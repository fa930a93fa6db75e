#pragma once
// The [render] keys every random walk of a camera path shares, whichever integrator runs it:
//
//   | key       | default | meaning                                                           |
//   |-----------|---------|-------------------------------------------------------------------|
//   | max_depth | -1      | scattering events per path; -1: unlimited (unbiased)              |
//   | rr_depth  | 5       | Russian roulette from this many scattering events on              |
//   | mis       | true    | light sampling and phase / BSDF sampling combined by the power    |
//   |           |         | heuristic (transport/mis.h); false: light sampling only           |
//   | equiangular | false | point and spot lights' single scattering along each segment also  |
//   |           |         | sampled equiangularly, combined with the distance sampling by the |
//   |           |         | balance heuristic (transport/equiangular.h); false: distance only |
namespace vpm {

class Params;

struct WalkSettings {
    int max_depth = -1;
    int rr_depth = 5;
    bool mis = true;
    bool equiangular = false;   // docs/studies/equiangular.md: measured, not yet the default
    // Reads max_depth, rr_depth, mis and equiangular from the [render] table; throws ConfigError.
    static WalkSettings read(Params& render);
};

}  // namespace vpm
