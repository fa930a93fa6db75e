#include "render/plan/no_map_stop.h"

#include <algorithm>
#include <cmath>

#include "core/math.h"
#include "render/plan/no_map_candidate.h"

namespace vpm {

double variance_lower_factor(double rel_se) {
    if (!(rel_se > 0.0)) return 1.0;   // every squared deviation alike: the variance is exact
    const double k = 1.0 / (rel_se * rel_se);
    const double c = 1.0 - 1.0 / (9.0 * k) - kNoMapStopSigmas / (3.0 * std::sqrt(k));
    return c > 0.0 ? c * c * c : 0.0;
}

NoMapStopTest no_map_stop_test(const PlanInputs& in, size_t c) {
    NoMapStopTest t;
    t.best_map_score = kInfinity;
    const PassPlan plan = plan_passes(in);
    for (size_t i = 0; i < in.candidates.size(); ++i) {
        const GatherMeasurement& m = in.candidates[i];
        if (m.uses_map && !m.dropped && map_used_share(m) > kNoMapMaxUsedShare)
            t.best_map_score = std::min(t.best_map_score, plan.score[i]);
    }
    const GatherMeasurement& m = in.candidates.at(c);
    const double low = variance_lower_factor(m.v_camera_rel_se);
    if (!(low > 0.0) || !(m.v_camera > 0.0)) return t;   // its variance is not resolved from 0
    t.low_score = score_at_camera_variance(in, c, m.v_camera * low);
    t.stop = std::isfinite(t.best_map_score) && t.low_score > kNoMapStopMargin * t.best_map_score;
    return t;
}

}  // namespace vpm
