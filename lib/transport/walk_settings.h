#pragma once
// The [render] keys every random walk of a camera path shares, whichever integrator runs it:
//
//   | key       | default | meaning                                                           |
//   |-----------|---------|-------------------------------------------------------------------|
//   | max_depth | -1      | scattering events per path; -1: unlimited (unbiased)              |
//   | rr_depth  | 5       | Russian roulette from this many scattering events on              |
namespace vpm {

class Params;

struct WalkSettings {
    int max_depth = -1;
    int rr_depth = 5;
    // Reads max_depth and rr_depth from the [render] table; throws ConfigError.
    static WalkSettings read(Params& render);
};

}  // namespace vpm
