#pragma once
// Error metrics of rendered images against a reference, used by `vpm sweep`.
// Every definition the sweep reports lives here; docs/experiments.md, "Parameter sweeps", documents them.
//
// Pixels are compared by luminance Y = 0.2126 R + 0.7152 G + 0.0722 B. "Relative" means divided
// by the reference's MEAN luminance over the image, L = mean_p Y(ref_p) (squared for squared
// quantities), not per pixel: per-pixel ratios blow up on black or nearly black pixels (the
// background, shadowed floor). So relative RMSE 0.05 = a root-mean-square pixel error of 5% of
// the image's mean brightness.
//
// For one image I against the reference R (P pixels, finite ones only):
//   rel_rmse       = sqrt(mean_p (I_p - R_p)^2) / L
//   rel_mean_error = mean_p (I_p - R_p) / L          (signed; brightness bias of this image)
// For R repeats I_1..I_R of one configuration (independent photon maps and camera samples),
// with per-pixel mean M_p = mean_r I_rp and unbiased sample variance s2_p = sum_r (I_rp - M_p)^2/(R-1):
//   rel_mse        = mean_r mean_p (I_rp - R_p)^2 / L^2      (empirical mean squared error)
//   rel_variance   = mean_p s2_p / L^2                       (variance of one run, per pixel, averaged)
//   rel_bias2      = mean_p [(M_p - R_p)^2 - s2_p / R] / L^2 (unbiased estimate of the squared
//                                                            per-pixel bias; may come out < 0 by noise)
//   so that rel_mse = rel_bias2 + rel_variance EXACTLY (algebraic identity, tested).
//   rel_std        = sqrt(rel_variance)
//   rel_rmse       = sqrt(rel_mse)
//   rel_bias       = mean_r rel_mean_error(I_r) = mean_p (M_p - R_p) / L (signed per-pixel bias,
//                    averaged), rel_bias_se = sample std of the R per-repeat values / sqrt(R).
// The reference's own noise is part of every error (it adds its variance to rel_mse and to
// rel_bias2); render the reference with many more samples than the runs.
// Non-finite pixels (NaN/Inf in any channel) are counted in nonfinite_pixels and left out of the
// sums (a pixel is left out of the repeat metrics if it is non-finite in any repeat); the count
// must be 0 and the sweep reports it, never hides it.
#include <cstddef>
#include <vector>

#include "render/run/image.h"

namespace vpm {

double luminance(float r, float g, float b);

// Mean luminance of the reference; throws vpm::Error if it is not finite and positive.
double reference_scale(const Image& reference);

struct RunError {
    double rel_rmse = 0;
    double rel_mean_error = 0;
    size_t nonfinite_pixels = 0;
    size_t pixels = 0;   // compared (finite) pixels
};
// Throws vpm::Error if the sizes differ.
RunError run_error(const Image& image, const Image& reference);

struct RepeatError {
    size_t repeats = 0;
    double rel_rmse = 0, rel_mse = 0;
    double rel_bias = 0, rel_bias_se = 0;   // se: NaN for one repeat
    double rel_bias2 = 0;                   // for R = 1: (M - R)^2 (variance unknown)
    double rel_variance = 0, rel_std = 0;   // NaN for one repeat
    size_t nonfinite_pixels = 0;            // (pixel, repeat) pairs
    size_t pixels = 0;
};
// Needs at least one image; all the size of the reference.
RepeatError repeat_error(const std::vector<const Image*>& images, const Image& reference);

// Channel-wise error of one image (used by `vpm compare` next to run_error): every pixel and
// channel counts alike, and "relative" divides by the reference's mean over all channels.
//   rmse          sqrt(mean (a - r)^2)
//   relative_rmse rmse / mean(r)            (0 when mean(r) is 0)
//   relative_bias mean(a) / mean(r) - 1     (overall brightness error, e.g. the estimator bias)
struct ImageError {
    double rmse = 0.0;
    double relative_rmse = 0.0;
    double relative_bias = 0.0;
    double mean = 0.0;            // mean of the image
    double reference_mean = 0.0;  // mean of the reference
    size_t nonfinite = 0;         // non-finite values in either image (left out of all sums)
};

// Throws vpm::Error when the sizes differ.
ImageError compare_images(const Image& image, const Image& reference);

}  // namespace vpm
