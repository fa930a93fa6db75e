#pragma once
// The auto pilot's cost bound (render/plan/map_noise_pilot.h), in counted work units, never the clock.
// Under render.time_limit the whole pilot may take kPilotBudgetFraction of the plan's budget,
// shared equally by the candidates it traces. Each candidate first traces one probe sample per pilot
// pixel with the full map, which gives its counted work per sample; it then takes as many samples
// per pixel (at least 2, for a variance; at most kPilotSamples) as its share pays for with every
// map it traces (3: the map and its halves; 1 without a map). A candidate whose pass of one sample
// per pixel alone costs more than a planned pass may (the budget over kPlanMinPasses) cannot be
// planned except at the configured size, where a cheaper candidate always fits: it stops after its
// probe, dropped: an unbounded march pilot in a dense box could spend most of a short budget
// (docs/studies/auto_plan.md, section 11.7).
#include <algorithm>
#include <cmath>
#include <limits>

namespace vpm {

constexpr double kPilotBudgetFraction = 1.0 / 8.0;
constexpr int kPilotMinSamples = 2;

struct PilotBudget {
    double per_candidate = 0.0;   // work units a candidate may spend; 0: unbounded (no time limit)
    double max_pass_cost = std::numeric_limits<double>::infinity();   // a one-sample pass above this: dropped
};

// Samples per pixel and map within `share` units, given the probe's cost per sample, `pixels`
// pilot pixels and `maps` maps per sample, the probe (one full-map sample per pixel) included.
inline int pilot_samples(double share, double cost_per_sample, int pixels, int maps, int most) {
    if (!(share > 0.0) || !(cost_per_sample > 0.0)) return most;
    const double n = std::floor(share / (double(pixels) * double(maps) * cost_per_sample));
    return int(std::clamp(n, double(kPilotMinSamples), double(most)));
}

}  // namespace vpm
