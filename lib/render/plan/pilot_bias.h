#pragma once
// The squared bias the auto plan charges a map of N0 photons (render/plan/pass_plan.h), read from the
// pilot's half maps (render/plan/map_noise_pilot.h): per sample, d = (a + b) / 2 - f, the half maps'
// mean minus the full map's with the same random numbers, so that d holds the maps' difference
// alone. For a bias ~ r^2 ~ N^-2/3 (the corrected estimate's in a smooth density) E[d] is
// (2^(2/3) - 1) times the full map's bias.
//
// Each pixel's d also carries the map noise of that difference, the same for all of its samples:
// squared per pixel it is a positive floor that no number of samples removes. In the uniform
// furnace (zero smoothing bias) that floor read as a squared bias of 3.2e-5 .. 9.4e-4 (1-6% of the
// radiance 0.5; 11 of 12 above 2.3e-4) for the two map gathers over six seeds, and in the shared smoke sample it flipped the
// plan between 1e5 photons x 16 samples and 1.6e6 x 128 by seed (docs/studies/auto_plan.md section 17). So the
// bias is pooled with its sign over the pilot's pixels instead, each pixel's mean of d one
// observation: their spread, map noise included (the pixels see different parts of the map), gives
// the standard error, and the squared pooled mean, less its own variance, bounds the mean squared
// bias of a pixel from below. A bias that cancels between pixels is not seen; one that the pilot
// does not resolve (within kPilotBiasSigmas standard errors of zero) is charged as 0.
#include <vector>

namespace vpm {

// Standard errors the pooled difference must clear before the plan pays for it: at 3 a zero bias
// is charged in 0.3% of a candidate's pilots.
constexpr double kPilotBiasSigmas = 3.0;

struct PilotBias {
    double mean = 0.0;    // the full map's bias at N0, pooled over pixels and samples (luminance, signed)
    double se = 0.0;      // its standard error
    double bias2 = 0.0;   // squared bias charged: mean^2 - se^2 where resolved, else 0
};

// a, b, f: the two half maps' and the full map's sample values, pixel j's sample s at
// j * stride + s, for `pixels` pixels of `samples` samples each (at least 2 pixels, 1 sample).
// weights: per pixel, the weight of its squared error (render/plan/relative_error.h): each pixel's
// mean difference is taken times its square root, so that bias2 is the relative squared bias; empty: 1.
PilotBias pooled_half_map_bias(const std::vector<double>& a, const std::vector<double>& b,
                               const std::vector<double>& f, int pixels, int samples, int stride,
                               const std::vector<double>& weights = {});

}  // namespace vpm
