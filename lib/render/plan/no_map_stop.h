#pragma once
// The early stop of the pilot of the candidate without a map (render/plan/no_map_candidate.h). Its
// pilot takes up to kNoMapPilotSamples per pilot pixel (render/plan/map_noise_pilot.h) to see its
// tail; where it loses to a map candidate by far, those samples buy nothing and their time is the
// run's. So it is measured in stages (kNoMapStopFirstStage samples per pilot pixel, doubling), and
// after each it stops where its score (render/plan/pass_plan.h) at a lower confidence bound on its
// camera variance still exceeds kNoMapStopMargin times the best map candidate's score, as the plan
// charges it (its upper bound). Stopped, it is not a choice.
// The bound: the variance read is held by k = 1 / rel_se^2 samples' worth (render/plan/pilot_tail.h:
// rel_se from the few samples that hold it), and a count seen k times has a one-sided Poisson lower
// limit kNoMapStopSigmas standard deviations down (Wilson-Hilferty: k (1 - 1/9k - z/3 sqrt k)^3); the
// variance is bounded by that share of it. Where a few rare samples hold it (small k, as in the
// caustic scenes) the normal bound 1 - z / sqrt k is 0 and could never stop the pilot; the Poisson
// limit stays above 0 from k ~ 1.3. A tail its first samples miss reads the variance low, so that
// seen it loses by more. Where it wins or is close the test does not fire and its samples, figures
// and choice are the full pilot's. From counts and fixed samples alone: the same on any thread count.
#include <cstddef>

#include "render/plan/pass_plan.h"

namespace vpm {

constexpr double kNoMapStopSigmas = 3.0;
constexpr double kNoMapStopMargin = 2.0;

struct NoMapStopTest {
    bool stop = false;
    double low_score = 0.0;        // the candidate's score at its camera variance's lower bound (0: none resolved)
    double best_map_score = 0.0;   // the least score of a map candidate that may be chosen (infinite: none)
};

// The share of a variance read with relative standard error rel_se that bounds it from below.
double variance_lower_factor(double rel_se);

// The test on candidate c (without a map) of in.candidates, every figure as measured so far. Map
// candidates that almost never use their map are no reference (render/plan/no_map_candidate.h: they
// are the continuation plus a photon pass).
NoMapStopTest no_map_stop_test(const PlanInputs& in, size_t c);

}  // namespace vpm
