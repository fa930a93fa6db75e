#pragma once
// Error metrics of rendered images against a reference: every number `vpm compare`, sweeps,
// `vpm render --reference`, `vpm bench` and vpm.compare report is computed here; docs/metrics.md
// documents them for users.
//
// The named metrics (measure_error; ErrorMetric), on luminance Y, over the compared pixels
// (a PixelMask may leave some out):
//   relMSE  = mean_p (Y_I - Y_R)^2 / (Y_R^2 + eps)       eps = 0.01 by default: the per-pixel
//             relative MSE rendering papers report; no pixel dominates it (a glint whose error is
//             10x its value weighs 100, not 100 x its brightness^2). The default.
//   relRMSE = sqrt(mean_p (Y_I - Y_R)^2) / L              L = mean_p Y_R over the compared pixels:
//             linear, normalised by the image's mean brightness; a few bright pixels decide it.
//   SMAPE   = mean_p |Y_I - Y_R| / (|Y_I| + |Y_R| + eps) symmetric absolute percentage error, in [0, 1).
// With the reference's per-pixel variance v_p (the variance of Y_R as an estimate; reference_noise.h),
// each squared metric has a noise floor, the score a perfect image would get against this noisy
// reference, which is subtracted:
//   relMSE : floor = mean_p v_p / (Y_R^2 + eps)           value = raw - floor
//   relRMSE: floor = sqrt(mean_p v_p) / L                 value = sign(d) sqrt(|d|), d = raw^2 - floor^2
// (a negative value: the image's error is below what the reference can resolve). SMAPE is not a
// sum of squares, so no floor is subtracted from it (floor NaN).
//
// The older sweep columns below (RunError, RepeatError: relative to the mean luminance L) stay as
// they are; the sweep reports them beside the named metric.
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
#include <string>
#include <vector>

#include "analysis/metrics/pixel_mask.h"
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

enum class ErrorMetric { rel_mse, rel_rmse, smape };

constexpr double kDefaultMetricEpsilon = 0.01;

// "relmse", "relrmse" or "smape" (case-insensitive; "rel_mse", "rel_rmse" too); throws vpm::Error
// naming the allowed values otherwise.
ErrorMetric parse_error_metric(const std::string& name);
// "relMSE", "relRMSE", "SMAPE": how reports name it.
std::string metric_name(ErrorMetric metric);
// The formula in one line, e.g. "relMSE = mean (I - R)^2 / (R^2 + 0.01) over luminance".
std::string metric_formula(ErrorMetric metric, double epsilon);
// true for the metrics whose reference noise is subtracted (relMSE, relRMSE).
bool metric_has_floor(ErrorMetric metric);

struct MetricOptions {
    ErrorMetric metric = ErrorMetric::rel_mse;
    double epsilon = kDefaultMetricEpsilon;   // relMSE's and SMAPE's denominator guard (> 0)
    const PixelMask* mask = nullptr;          // null: every pixel
};

struct MetricValue {
    ErrorMetric metric = ErrorMetric::rel_mse;
    double epsilon = kDefaultMetricEpsilon;
    double value = 0;    // the metric, the reference's noise floor subtracted when it is known
    double raw = 0;      // the metric against the reference as it is
    double floor = 0;    // what a perfect image would score against this reference; NaN: unknown
    size_t pixels = 0;             // compared pixels
    size_t masked_out = 0;         // left out by the mask
    size_t nonfinite_pixels = 0;   // non-finite in the image (left out and counted: must be 0)
    bool floor_known() const;
};

// The image's error against the reference by options.metric. reference_variance: per-pixel variance of
// the reference's luminance (reference_noise.h; any channel, they are equal), or null when unknown
// (floor NaN, value = raw). Throws vpm::Error when sizes differ, the reference has a non-finite
// compared pixel, no pixel is compared, or (relRMSE) the compared reference mean is not positive.
MetricValue measure_error(const Image& image, const Image& reference, const MetricOptions& options,
                          const Image* reference_variance = nullptr);

// One line for a report: "relMSE 0.0123 (raw 0.0150 - reference noise floor 0.0027; 4096 pixels)".
std::string describe(const MetricValue& value);

}  // namespace vpm
