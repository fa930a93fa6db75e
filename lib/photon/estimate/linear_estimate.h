#pragma once
// photons.extinction = "linear": the ball normalisation made exact for a radiance that
// varies linearly across the kNN ball.
//
// The ball normalisation estimates the sigma_t-weighted mean of the incident radiance L over
// B(x, r_k), i.e. L at the ball's sigma_t centroid c, not at x. Where the ball is clipped by the
// medium's boundary, c lies inside the medium, away from x, and the radiance under a lit
// boundary climbs steeply with depth (docs/dense_bias.md): the estimate reads L deeper than x,
// too high by about (c - x) . grad L. With the sigma_t moments of the ball (m0, c, covariance S;
// photon/estimate/ball_extinction.h) every photon's weight is multiplied by
//
//     h_i = 1 - (y_i - c)^T S^-1 (c - x)
//
// so that sum h_i w_i / m0 is exact in expectation when L is linear over the ball: given r_k the
// k - 1 inner photons are i.i.d. with density sigma_t L / integral(sigma_t L) over the ball, so
// E[sum h w | r_k] = (k - 1) m0 L(x) / Lambda(r_k), and E[(k - 1) / Lambda(r_k)] = 1 (Lambda(r_k) ~
// Gamma(k)): the k - 1 correction carries over unchanged. Where c = x (a ball of constant sigma_t
// inside the medium) every h_i is 1 and the estimate is the ball normalisation's, bit for bit up to
// rounding. A covariance too flat to invert (the medium's mass in a sheet) keeps h = 1.
//
// Non-negative by construction: the weights h_i are negative for photons deep in a clipped ball
// (h ranges over about [-3, 3.4] in a half-ball), so where a few photons carry most of the sum
// (a strongly anisotropic phase function, g near -1 or 1, or a tiny k) the corrected sum can go
// negative, which no radiance is (no boundary correction unbiased for every linear radiance is
// non-negative for every sample). Such an estimate falls back to the ball normalisation (every
// h_i = 1, >= 0 since the powers and kernel weights are), counted in photons.linear_fallbacks.
// Every estimate that does not fall back is unchanged bit for bit. The fallback raises the mean by
// E[(ball - linear) 1{linear < 0}]: nothing where no query falls back, +1.9% at g = -0.95 in
// configs/homogeneous.toml, where the linear mean is right only through its negative estimates
// (docs/linear_fallback.md).
#include <cstdint>
#include <vector>

#include <Eigen/Eigenvalues>

#include "photon/estimate/ball_extinction.h"
#include "photon/estimate/estimators.h"

namespace vpm {

// True if any channel of a linear-corrected sum is negative (NaN is not: it is counted elsewhere).
inline bool linear_sum_negative(const Rgb& v) { return (v.array() < 0.0).any(); }

// Incident radiance (sigma_t-normalised estimate) at x from the estimate s gathered into buf with
// estimator e, the ball's moments m (m.m0 > 0), and the map for the photon positions. fallbacks (may
// be null) counts the estimates that fell back to the ball normalisation (negative corrected sum);
// keep_negative (photons.extinction = "linear_signed") returns them as they are instead, counted the
// same way: no fallback, so the mean stays exact for a linear radiance, and an estimate may be negative.
inline Rgb linear_estimate(const Estimate<Rgb>& s, const Estimator& e, const GatherBuffers& buf, const PhotonMap& map,
                           const Vec3& x, const BallMoments& m, std::vector<Rgb>& scratch, uint64_t* fallbacks = nullptr,
                           bool keep_negative = false) {
    const double volume = ball_volume(3, s.radius);
    const double mean = m.m0 / volume;
    const bool used = s.kind == EstimateCase::knn || s.kind == EstimateCase::extended ||
                      s.kind == EstimateCase::all_photons || s.kind == EstimateCase::fixed_radius;
    if (!used || !(volume > 0.0) || s.k_used == 0) return s.value / mean;
    // The centroid at x exactly (a ball inside a homogeneous medium, closed-form moments): every
    // h_i is 1, and the weighted sum below would be s.value bit for bit.
    if (m.offset.isZero(0.0)) return s.value / mean;
    // S^-1 (c - x), if S is comfortably positive definite (relative to r^2).
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(m.cov);
    if (!(eig.eigenvalues().minCoeff() > 1e-6 * s.radius * s.radius)) return s.value / mean;
    const Vec3 g = eig.eigenvectors() * (eig.eigenvalues().cwiseInverse().asDiagonal() * (eig.eigenvectors().transpose() * m.offset));
    if (scratch.size() < s.k_used) scratch.resize(s.k_used);
    const Vec3 c = x + m.offset;
    for (size_t i = 0; i < s.k_used; ++i) scratch[i] = buf.w[i] * (1.0 - (map.position(buf.list[i].index) - c).dot(g));
    // The estimator's own ball (r_k or R); its radius scale, if any, counts within s.radius again.
    const double knn_volume = s.knn_radius == s.radius ? volume : ball_volume(3, s.knn_radius);
    const Neighbours<Rgb> n{scratch.data(), buf.d2.data(), s.k_used, s.knn_radius, knn_volume, 3};
    const Rgb value = s.kind == EstimateCase::fixed_radius ? e.fixed_radius(n) : e.apply(n);
    if (linear_sum_negative(value)) {
        if (fallbacks) ++*fallbacks;   // with keep_negative: the negative estimates kept
        if (keep_negative) return value / mean;
        return s.value / mean;
    }
    return value / mean;
}

}  // namespace vpm
