#pragma once
// The auto pilot's heavy-tail figures (render/plan/no_map_candidate.h): how many of a candidate's samples
// hold its variance. Each sample's squared deviation from its own pilot pixel's mean (pixels differ in
// mean: pooled, their spread would look like a tail) is one entry.
//
// The relative standard error of their mean is what the plan charges a candidate without a map
// (render/plan/pass_plan.h). The share held by the largest fraction is reported (the sidecar's
// tail_share): with the fraction fixed, a light-tailed estimator gives about the same share at any
// sample count, a tail whose rare samples carry the variance a share near 1. On the pilot's
// "continue" samples at 64 pixels x 128-1024 samples (docs/studies/auto_plan.md section 16) the top 1/1024 held
// 0.84-0.96 in the g = 0.8 cells under a point light and 0.05-0.35 in the g = 0 cells with short
// continued paths; 0.97 in a thin fog under a spot light (section 29), whose rare collisions are a
// tail the map shares, so the share alone does not say which candidate the tail favours.
#include <vector>

namespace vpm {

// The share of the sum of `squares` (non-negative) held by its largest ceil(fraction x size) entries;
// 0 for an empty or all-zero input. Deterministic: a sum of the same values in a fixed order.
double largest_squares_share(std::vector<double> squares, double fraction);

// The relative standard error of the mean of `squares` (non-negative; the pilot's variance read from
// them): sqrt(sum q^2 / (sum q)^2 - 1/n), i.e. sqrt(1/n_eff - 1/n) with n_eff = (sum q)^2 / sum q^2
// the number of samples that effectively hold the variance. Light-tailed samples give ~sqrt(8/n)
// (exponential); a variance held by a few samples gives up to ~1. 0 for an empty or all-zero input.
double mean_of_squares_relative_se(const std::vector<double>& squares);

}  // namespace vpm
