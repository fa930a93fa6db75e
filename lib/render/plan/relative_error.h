#pragma once
// The error the auto plan minimises (render/plan/pass_plan.h) is the relative MSE per pixel that the
// renderer is judged by, mean over pixels of (I - R)^2 / (R^2 + eps) on luminance
// (analysis/metrics/error_metrics.h: relMSE, eps = kDefaultMetricEpsilon, the same value). The pilot
// (render/plan/map_noise_pilot.h) therefore weights each pixel's variance, map variance and bias by
// 1 / (R^2 + eps), with R the pixel's mean over every candidate's pilot samples (each candidate's
// pixel mean one estimate of the same pixel, weighted alike): a weight common to the candidates, so
// that it ranks them and does not reward one for reading a pixel low.
// A linear per-sample variance lets the few brightest pixels decide (a lamp seen through glass,
// luminance ~800, against a room at ~0.3: glass_bulb_smoke chose the path tracer at 318x the photon
// map's relMSE, docs/studies/caustic_scenes.md); relative, each pixel counts by its own error.
namespace vpm {

constexpr double kRelativeErrorEpsilon = 0.01;

// The weight of a pixel of mean `reference` in the relative MSE.
inline double relative_error_weight(double reference) { return 1.0 / (reference * reference + kRelativeErrorEpsilon); }

}  // namespace vpm
