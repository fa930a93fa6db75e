#pragma once
// photons.neighbours = "walks": the kNN density estimate with walks, not photons, as the
// independent units (derivation, variance and measurements: docs/walk_correlation.md).
//
// The k - 1 correction of estimators.h is exact for independent photons (a Poisson or binomial
// field): given r_k the k - 1 inner photons are i.i.d. in the ball. A photon map stores every real
// collision of a random walk, so the photons of one walk lie along a trail; where siblings of one
// walk share a kNN ball, r_k comes early and the photon-neighbour estimates read high. The walks
// themselves are independent. Let R be the distance at which the k-th distinct walk is first met
// (the k-th smallest of the walks' nearest-photon distances). Then, with w_i the weighted photon
// powers and omega the kernel weight at t_i = r_i / R (estimators.h),
//
//   walk corrected  S = sum_{r_i <  R} w_i omega(t_i) / V(R)   the photons of the k - 1 nearer walks
//   walk classic    S = sum_{r_i <= R} w_i omega(t_i) / V(R)   plus the k-th walk's photon at R
//
// (V(R) the ball volume in `dim` dimensions, or the renderer's ball integral of sigma_t). For N
// i.i.d. walks F(R) = P(a walk comes within R of x) ~ Beta(k, N - k + 1), and given R the k - 1
// nearer walks are i.i.d. walks conditioned to enter B(R): E[S | R] = (k - 1) M(R) / (F(R) V(R)),
// M(R) the mean weighted power one walk leaves in B(R). With N M(R) = rho V(R) on a uniform
// density and E[1/F(R)] = N / (k - 1): E[walk corrected] = rho, however the photons of a walk
// cluster. Walk classic adds E[w_k omega(1) / V(R)]: k1/(k - 1) of rho for independent photons (the
// seed's k/(k - 1)), less when walks leave several photons in a ball (docs/walk_correlation.md).
//
// The walk neighbourhood is a different list, not a different estimator: the registry's "classic"
// and "corrected" are applied to it with k' = its length (the last entry is the k-th walk's first
// photon), so every kernel, radius scale and rule of estimators.h carries over:
//  (a) fewer than k walks within a finite max_radius: the fixed-radius estimate over B(max_radius).
//  (b) fewer than k walks in the whole map (no max_radius): every photon, the farthest as the k-th.
//  (c) R unresolvable (coincident photons): the ball extends to the first farther photon, gathering
//      more walks as needed.
// "mse_optimal" has no walk form (its shrink assumes independent photons): refused.
#include <string>
#include <vector>

#include "photon/estimate/estimators.h"
#include "photon/map/photon_map.h"
#include "photon/map/walk_set.h"

namespace vpm {

// photons.neighbours: which units the k nearest are counted in.
enum class Neighbourhood { photons, walks };
const char* neighbourhood_name(Neighbourhood n);
const std::vector<std::string>& neighbourhood_names();   // "photons", "walks"
// Throws vpm::Error naming `key`, the value and the allowed values.
Neighbourhood parse_neighbourhood(const std::string& value, const std::string& key = "photons.neighbours");

// Throws vpm::Error unless e has a walk form ("classic" or "corrected", any kernel and radius scale).
void validate_walk_estimator(const Estimator& e);

// The estimate over a walk neighbourhood: w, d2 the `found` photons of PhotonMap::knn_walks sorted by
// distance (their walks in `walk_of(i)`), complete: the list holds every photon within max_radius
// (knn_walks found fewer walks than asked). Applies e with the rules above; need_more (rule (c)
// ran out of list) tells the caller to gather more walks and call again. stats may be null.
template <class T, class WalkOf>
Estimate<T> estimate_density_walks(const Estimator& e, const T* w, const double* d2, size_t found, const WalkOf& walk_of,
                                   bool complete, size_t k, double max_radius, int dim, std::vector<uint32_t>& slots,
                                   EstimatorStats* stats = nullptr, double coincident_radius = 0.0) {
    validate_walk_estimator(e);
    e.validate_k(k);
    size_t walks = 0;
    const size_t end = walk_neighbourhood_size(found, k, walk_of, slots, walks);
    Estimate<T> out;
    if (walks < k) {
        if (!complete) throw Error("estimate_density_walks: fewer than k walks but the list is not complete");
        if (std::isfinite(max_radius) || found < e.min_k()) {
            // Rule (a) (or an empty/too short list): estimate_density's own fixed-radius/insufficient cases.
            return estimate_density<T>(e, w, d2, found, true, std::max(found + 1, e.min_k()), max_radius, dim, stats,
                                       coincident_radius);
        }
        out = estimate_density<T>(e, w, d2, found, true, found, max_radius, dim, nullptr, coincident_radius);
        if (out.kind == EstimateCase::knn) out.kind = EstimateCase::all_photons;   // rule (b)
    } else {
        out = estimate_density<T>(e, w, d2, found, complete, end, max_radius, dim, nullptr, coincident_radius);
    }
    if (stats && out.kind != EstimateCase::need_more) stats->count(out.kind);
    return out;
}

// The photon-map front ends, as estimate_in_scattering and estimate_surface_irradiance
// (estimators.h) with walk neighbourhoods: in-scattering (dim 3, HG phase weights) and surface
// irradiance (dim 2, photons from the other side weigh 0 but count as walks).
Estimate<Rgb> estimate_in_scattering_walks(const PhotonMap& map, const Vec3& x, const Vec3& w_o, double g, Estimator e,
                                           size_t k, double max_radius, GatherBuffers& buf,
                                           EstimatorStats* stats = nullptr);
Estimate<Rgb> estimate_surface_irradiance_walks(const PhotonMap& map, const Vec3& x, const Vec3& n, Estimator e,
                                                size_t k, double max_radius, GatherBuffers& buf,
                                                EstimatorStats* stats = nullptr);

}  // namespace vpm
