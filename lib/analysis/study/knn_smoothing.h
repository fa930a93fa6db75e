#pragma once
// The mean of the corrected kNN estimate of independent photons under a lit face, with the local-linear
// weights of photons.extinction = "linear" (photon/estimate/linear_estimate.h): the smoothing a ball of
// random radius makes (docs/walk_correlation.md section 6).
//
// Points of a Poisson process with density lambda(d), d the depth below a plane face (the medium is
// d >= 0), a query at depth z. Given r_k the k - 1 inner points are i.i.d. with density lambda over
// the clipped ball B, so the corrected sum's mean given r_k is (k - 1) F(r_k) / Lambda(r_k), with
//     F(r)      = integral_B h lambda / m0   (the fixed-radius estimate's mean at radius r),
//     Lambda(r) = integral_B lambda          (the ball's mean count),
// h the linear weight 1 - (y - c) . S^-1 (c - x) of the clipped ball's centroid c and covariance S,
// m0 its volume. Lambda(r_k) ~ Gamma(k, 1), and (k - 1) gamma_k(t) / t = gamma_{k-1}(t), hence
//     E[corrected] = E[ F(Lambda^-1(T)) ],   T ~ Gamma(k - 1, 1):
// the fixed-radius mean at a random radius whose ball holds a Gamma(k - 1) count. The estimate is
// unbiased where F(r) = lambda(z) for every r (lambda linear over every ball); otherwise its bias is
// the fixed-radius smoothing F(r) / lambda(z) - 1 averaged over that radius. With N points in all
// instead of a Poisson count, T = N P with P ~ Beta(k - 1, N - k + 1) (relative difference O(k / N)).
// Not modelled: the linear estimate's fallback to the ball normalisation where its sum is negative.
//
// Slices: in a ball of radius r around depth z, the slice at depth z + u (max(-r, -z) <= u <= r)
// is a disc of area pi (r^2 - u^2); only the depth enters (lateral moments are symmetric).
#include <cstddef>
#include <functional>

namespace vpm {

using DepthDensity = std::function<double(double depth)>;

struct ClippedBallMeans {
    double fixed_radius = 0.0;   // F(r)
    double mass = 0.0;           // Lambda(r)
    double mass_rate = 0.0;      // dLambda / dr
};

// F, Lambda and dLambda/dr of the ball of radius r > 0 at depth z >= 0 (Gauss-Legendre, 64 nodes over
// the slices' range: exact for polynomial densities of degree up to 124, the slice area and the weight
// adding 3).
ClippedBallMeans clipped_ball_means(const DepthDensity& density, double z, double r);

// E[corrected] at depth z for k >= 2: F averaged over the radius at which Lambda = T ~ Gamma(k - 1).
// Integrated over r up to where Lambda passes T's 1 - 1e-12 quantile (at most max_radius; past it
// the rest of the mass is dropped), on `steps` panels of Simpson's rule.
double corrected_knn_mean(const DepthDensity& density, double z, size_t k, double max_radius = 50.0, int steps = 4000);

}  // namespace vpm
