#pragma once
// One trial of the study's "beam" scenario (analysis/study/study.h): the sample-point estimate
// (photon/estimate/sample_point_estimate.h, the estimate behind photons.gather = "beam") on n points
// uniform in the unit torus, so the density is uniform with no boundary at all. Each point's
// radius is its k-th nearest *other* point (minimal-image distance); the point estimate is taken
// at the cube's centre (3D kernel) and the beam estimate along a segment of length `length`
// through it in a random direction (2D kernel over each point's disc, every periodic image of a
// point that the segment's disc test accepts counted). docs/beam_estimate.md: the mean is exactly
// M_d / n_d times the truth (1 for every normalised kernel) for every k, as the process is
// stationary; the radii must stay below 1/2 (the minimal image), which n >= 4 k guarantees in
// all but a vanishing fraction of trials (the caller checks n).
#include <cstddef>
#include <vector>

#include "core/sampling/rng.h"
#include "photon/estimate/kernels.h"

namespace vpm {

// Relative estimates (estimate / truth) written to point[ki * K + kk] and beam[ki * K + kk] for
// ks[ki] and kernels[kk] (K = kernels.size()). ks ascending, all < n.
void sample_point_trial(size_t n, double length, const std::vector<size_t>& ks, const std::vector<Kernel>& kernels,
                        Rng& rng, double* point, double* beam);

// First-order relative variance of the point estimate (q_3 / (k - 1)) and of the beam estimate
// (q_2 E[1 / (pi R^2)] / (rho L), E[R^-2] = (4/3 pi rho)^(2/3) Gamma(k - 2/3) / Gamma(k)), with
// q_d the kernel's variance factor, density rho (points per unit volume) and segment length L.
double sample_point_variance_3d(const Kernel& kernel, size_t k);
double sample_point_variance_beam(const Kernel& kernel, size_t k, double rho, double length);
// The mean's theory, relative to the truth: M_d / n_d (1 for every normalised kernel).
double sample_point_mean(const Kernel& kernel, int dim);

}  // namespace vpm
