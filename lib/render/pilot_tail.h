#pragma once
// The auto pilot's heavy-tail diagnostic (render/no_map_candidate.h): the share of a candidate's
// sample variance that its largest samples hold. Each sample's squared deviation from its own pilot
// pixel's mean (pixels differ in mean: pooled, their spread would look like a tail) is ranked, and the
// largest ceil(fraction x count) of them are summed against the total.
//
// With the fraction fixed, a light-tailed estimator gives about the same share at any sample count
// once the largest fraction holds several samples, while a tail whose rare samples carry the variance
// gives a share near 1. Measured on the pilot's "continue" samples at 64 pixels x 128-1024 samples
// (BENCHMARKS.md section 16): the top 1/1024 held 0.84-0.96 of the squared deviations in the g = 0.8
// cells under a point light (NEE through the forward lobe after a rare backward bounce) and 0.05-0.35
// in the g = 0 cells with short continued paths (up to 0.53 in albedo-0.99 grids: long walks).
#include <vector>

namespace vpm {

// The share of the sum of `squares` (non-negative) held by its largest ceil(fraction x size) entries;
// 0 for an empty or all-zero input. Deterministic: a sum of the same values in a fixed order.
double largest_squares_share(std::vector<double> squares, double fraction);

}  // namespace vpm
