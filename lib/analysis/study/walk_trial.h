#pragma once
// The estimator study's `walks` scenario (analysis/study/study.h): photons that are not independent.
//
// Random walks in an infinite uniform medium (mean free path 1): a walk's first photon is uniform,
// each next one an Exp(1) flight further in an HG(g)-sampled direction, and the walk goes on with
// probability `albedo` after every collision (analog absorption, unit weights): photons per walk
// C ~ Geometric, E[C] = 1 / (1 - albedo). The medium is a periodic cube (a torus) holding `walks`
// walks, its side set so that the photon density is `density` per mfp^3 exactly: every photon is
// uniform in it, and a ball below half the side is a ball of the infinite medium. Each trial
// queries `queries` uniform points and reports each estimate / truth averaged over them (the
// trials are independent; the queries of one trial share its walks).
//
// Methods (columns, in this order):
//   classic, corrected   the photon-neighbour forms (estimators.h) at the k-th photon
//   walk_classic,        the walk-neighbour forms (photon/estimate/walk_estimate.h) at the k-th walk
//   walk_corrected
//   leave_group_out      photon/estimate/group_estimate.h's halves by walk parity (group = walk mod 16)
//
// Theory (docs/walk_correlation.md): walk_corrected and leave_group_out are exact (0) for i.i.d.
// walks. The others, to first order in the clustering, from s(R) = the mean number of same-walk
// siblings inside a ball per photon inside it (a ball of radius R at a uniform point), measured from
// the walk geometry alone (walk_clustering below: sibling distance pairs, no kNN):
//   corrected       b_c = (k - 1) int_0^inf s(m)/2 (p_{k-2}(m) - p_{k-1}(m)) dm / m
//   classic         k/(k - 1) (1 + b_c) - 1
// with m = density V(R) the expected photon count of the ball and p_j the Poisson pmf. Valid
// while s is small at the balls that matter (m ~ k); the study prints s there. walk_classic's
// theory is exact in the limit of many walks, from the walks that enter a ball rather than from s:
//   walk_classic    int_0^inf P(Poisson(m / c(m)) >= k) dm / m^2
// with c(R) = the mean photons inside the ball of a walk that enters it (the photons of one walk
// over the volume within R of it, measured by walk_clustering).
#include <cstddef>
#include <string>
#include <vector>

#include "core/sampling/rng.h"

namespace vpm {

struct WalkMedium {
    double albedo = 0.5;
    double g = 0.0;
    std::string label() const;   // "walks/a0.5/g0"
};
// 0.3, 0.5, 0.9, 0.99 with g 0 and 0.8.
const std::vector<WalkMedium>& study_walk_media();

// The column names, in the order above.
const std::vector<std::string>& walk_study_methods();

struct WalkTrialSettings {
    double density = 40.0;   // photons per mfp^3: the truth
    size_t walks = 4096;     // walks per trial (must be >= 16 k_max: radii below a quarter of the cube's side)
    size_t queries = 8;      // query points per trial
};

// One trial: out[ki * methods + m] = the mean over the queries of estimate / truth at ks[ki];
// photons = the photons the walks left.
void walk_trial(const WalkMedium& medium, const WalkTrialSettings& settings, const std::vector<size_t>& ks, Rng& rng,
                std::vector<double>& out, size_t& photons);

// s(R) and c(R) on a grid of radii, from `walks` independent walks (unwrapped): s from their
// sibling distances; c = photons per walk x V(R) / E[U(R)], U(R) the volume within R of one walk (the
// union of its photons' balls), by importance sampling `points` uniform points around each walk
// (drawn from `point_rng`).
struct WalkClustering {
    std::vector<double> radius, s, c;
    double photons_per_walk = 0;   // measured mean, for the notes
};
WalkClustering walk_clustering(const WalkMedium& medium, size_t walks, Rng& rng, double max_radius, Rng& point_rng,
                               size_t points = 64);

// Theory of the relative error of method `m` (index into walk_study_methods()) at k: first order in
// the clustering for classic and corrected, exact for the others.
double walk_theory_error(size_t method, size_t k, double density, const WalkClustering& c);

// s and c at the ball that holds k photons in expectation (m = k), for the notes.
double walk_siblings_at(size_t k, double density, const WalkClustering& c);
double walk_entering_photons_at(size_t k, double density, const WalkClustering& c);

}  // namespace vpm
