#pragma once
// The [render] keys every random walk of a camera path shares, whichever integrator runs it:
//
//   | key       | default | meaning                                                           |
//   |-----------|---------|-------------------------------------------------------------------|
//   | max_depth | -1      | scattering events per path; -1: unlimited (unbiased)              |
//   | rr_depth  | 5       | Russian roulette from this many scattering events on              |
//   | mis       | true    | light sampling and phase / BSDF sampling combined by the power    |
//   |           |         | heuristic (transport/mis.h); false: light sampling only           |
namespace vpm {

class Params;

struct WalkSettings {
    int max_depth = -1;
    int rr_depth = 5;
    bool mis = true;
    // Reads max_depth, rr_depth and mis from the [render] table; throws ConfigError.
    static WalkSettings read(Params& render);
};

}  // namespace vpm
