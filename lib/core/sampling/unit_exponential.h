#pragma once
// A unit exponential variate, -log(1 - u) for u = Rng::uniform(). 1 - u is exact (u is a multiple of
// 2^-53 in [0, 1)), so this is -log1p(-u) to rounding, at less than half the cost of log1p (the
// trackers draw one per tentative collision). Never negative, never infinite (1 - u >= 2^-53).
#include <cmath>

#include "core/sampling/rng.h"

namespace vpm {

inline double unit_exponential(Rng& rng) { return 0.0 - std::log(1.0 - rng.uniform()); }

}  // namespace vpm
