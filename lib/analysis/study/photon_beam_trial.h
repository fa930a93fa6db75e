#pragma once
// One trial of the study's "photon_beams" scenario (analysis/study/study.h): the balloon photon-beams
// estimate (render/photon_map/gathers/photon_beams_gather.h) of a uniform isotropic Poisson field of beams.
// Beams of length 1 with Poisson centres (density rho, so rho beam length per unit volume) and
// uniform directions fill the cube [-1.5, 1.5]^3; the query is the segment from (0, 0, -1/2) to
// (0, 0, 1/2). Every beam crossing it (photon_beam_crossing: the feet of the common perpendicular
// inside both segments) lies wholly in the cube as long as its distance u < 1/2, so the field seen
// by the query is stationary. The truth (the fluence integral along the query with unit power and
// unit sigma_s f) is rho x 1; rho is chosen so that 410 beams cross within u < 1/2 on average
// (more than 1.6 x 256 = the largest k: P(r_k > 1/2) is below 1e-20 at k = 256).
//
// docs/photon_beams.md derives the theory: the crossings' u form a Poisson process of rate mu on
// [0, inf) independent of their angles, so r_k ~ Gamma(k, mu), and with D = E[1/sin^2]/E[1/sin]^2
// over the crossings (pi^2 / 8 for isotropic beams), omega = K / n_1:
//   corrected  E = m1,                          Var = D m2 / (k - 2)
//   classic    E = m1 + k1 / (k - 1),
//              E[S^2] = [(k-1) D m2 + (k-1)(k-2) m1^2 + 2 (k-1) m1 k1 + D k1^2] / ((k-1)(k-2)),
// m1 = int_0^1 omega, m2 = int_0^1 omega^2, k1 = omega(1) (Kernel::moments(1)).
#include <cstddef>
#include <vector>

#include "core/sampling/rng.h"
#include "photon/estimate/kernels.h"

namespace vpm {

constexpr double kBeamFieldIsotropicD = 9.8696044010893586 / 8.0;   // pi^2 / 8

// Relative estimates written to out[(ki * K + kk) * 2 + c], c = 0 classic, 1 corrected, for ks[ki]
// (ascending, <= 256) and kernels[kk] (K = kernels.size()).
void photon_beam_trial(const std::vector<size_t>& ks, const std::vector<Kernel>& kernels, Rng& rng, double* out);

struct BeamBalloonTheory {
    double mean = 1.0, variance = 0.0;   // relative to the truth; variance +inf at k = 2
};
BeamBalloonTheory photon_beam_balloon_theory(const Kernel& kernel, size_t k, bool keep_kth,
                                             double d = kBeamFieldIsotropicD);

}  // namespace vpm
