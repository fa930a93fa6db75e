#pragma once
// The radius bound of a volume estimate in dense media (photons.max_radius_mfp).
//
// In a dense medium the photons sit in a skin a few mean free paths deep under the lit surface,
// and the kNN ball at a camera query spans many mean free paths (median r_k = 2.2, 15, 147, 1460
// mean free paths on configs/homogeneous.toml at sigma_t_scale 1e2 .. 1e5 with 1e6 photons): it
// averages the steep fluence profile of the skin and its boundary, and the image came out 1%, 15%,
// 34%, 35% too dark (docs/dense_media.md). The estimate is therefore bounded to a ball of at most
// c mean free paths at the query, R(x) = c / sigma_t(x), and where fewer than k photons lie in
// B(R) the camera path does not use the map at x at all: it scatters there and continues like the
// path tracer (whose estimate of the light arriving at x is unbiased) until a later collision whose
// ball is resolvable. With N the number of photons in B(R), for a Poisson process of intensity rho
// (estimators.h, rule (a)):
//
//     N >= k       the corrected kNN estimate (r_k <= R):   E[(k-1)/V(r_k); N >= k] = rho P(N >= k-1)
//     N == k - 1   0                                          (that mass is already counted above)
//     N <= k - 2   continue the path: an unbiased estimate of the same light, weight P(N <= k-2)
//
// which sums to rho exactly: the k-1 correction stays exact where the kNN radius is used, and the
// rest is path traced. (With classic or mse_optimal the first line is their own, biased, kNN
// estimate; the split is the same.) Exact only for independent photons, and only where the path
// continued past x does not meet the same photons again: where a walk stores many collisions close
// together N is overdispersed and the band no longer balances (+7% in the dense plume of
// bench/heldout/h25, 18 photons per storing walk), and a path continued because the map is sparse
// near x queries the same sparse map at its next collision (the furnace at the bound read 7% low
// with the decision split between walk halves of one map: docs/studies/heldout_scenes.md section 31).
//
// The integrator therefore decides apart (render/photon_map/photon_map_integrator.h): a decision map, traced
// once per run with a seed of its own and an eighth of photons.count, holds the photons the pass map
// would hold within the bound, scaled to its density (k N_decision / N_map of them, at least 4,
// within the ball that holds that many on average; N the emitted photons), or the path goes on;
// where it does, the estimate is the pass map's unbounded kNN estimate. Every vertex of a camera path, continued ones
// too, decides on one map and estimates on the other, independent one, so the switch is exact
// however the photons cluster (no zero band: given the decision map, each branch is unbiased). The
// rule below, on the estimate's own list, stays for maps given from outside without a decision map.
// The cost: one more kNN query per bounded query, and where the map is too coarse for the medium
// the camera path becomes a path-traced random walk (measured in docs/dense_media.md). When the map holds
// fewer than k photons (empty, or starved by photons.store_probability or a tiny photons.count) no
// ball holds k anywhere: the integrator continues the path without a query, bound or no bound, at
// the collision and at march points alike.
#include <algorithm>
#include <cmath>
#include <cstddef>

#include "photon/estimate/estimators.h"

namespace vpm {

// min(max_radius, mfp_bound / sigma_t); max_radius (kInfinity for none) when the bound is off
// (mfp_bound <= 0) or sigma_t is not positive.
inline double bounded_radius(double max_radius, double mfp_bound, double sigma_t) {
    if (!(mfp_bound > 0.0) || !(sigma_t > 0.0) || !std::isfinite(sigma_t)) return max_radius;
    return std::min(max_radius, mfp_bound / sigma_t);
}

enum class BoundedQuery { use_estimate, zero, continue_path };

// What to do with an estimate gathered within the bounded radius (see above). Estimates of the
// kNN proper (and rule (c)'s extended ball) are used; fewer than k photons in range: 0 for exactly
// k - 1, else continue the path.
inline BoundedQuery bounded_query(const Estimate<Rgb>& s, size_t k) {
    switch (s.kind) {
        case EstimateCase::knn:
        case EstimateCase::extended: return BoundedQuery::use_estimate;
        case EstimateCase::fixed_radius:   // (k_used >= k: rule (c), coincident photons fill the ball)
            if (s.k_used >= k) return BoundedQuery::use_estimate;
            return s.k_used + 1 == k ? BoundedQuery::zero : BoundedQuery::continue_path;
        case EstimateCase::empty: return k == 1 ? BoundedQuery::zero : BoundedQuery::continue_path;
        default: return BoundedQuery::continue_path;
    }
}

}  // namespace vpm
