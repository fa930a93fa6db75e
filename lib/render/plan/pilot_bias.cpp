#include "render/plan/pilot_bias.h"

#include <cmath>

#include "core/error.h"

namespace vpm {

PilotBias pooled_half_map_bias(const std::vector<double>& a, const std::vector<double>& b,
                               const std::vector<double>& f, int pixels, int samples, int stride,
                               const std::vector<double>& weights) {
    if (pixels < 2 || samples < 1 || stride < samples)
        throw Error("pooled_half_map_bias: at least 2 pixels and 1 sample per pixel");
    const size_t need = size_t(pixels - 1) * size_t(stride) + size_t(samples);
    if (a.size() < need || b.size() < need || f.size() < need)
        throw Error("pooled_half_map_bias: fewer values than pixels x samples");
    if (!weights.empty() && weights.size() != size_t(pixels)) throw Error("pooled_half_map_bias: one weight per pixel");
    // The half maps' balls are 2^(1/3) wider: their mean is off by (2^(2/3) - 1) times the full map's bias.
    const double shrink = std::pow(2.0, 2.0 / 3.0) - 1.0;
    double mean = 0.0, m2 = 0.0;
    for (int j = 0; j < pixels; ++j) {
        double d = 0.0;
        for (int s = 0; s < samples; ++s) {
            const size_t i = size_t(j) * size_t(stride) + size_t(s);
            d += 0.5 * (a[i] + b[i]) - f[i];
        }
        d /= samples;
        if (!weights.empty()) d *= std::sqrt(weights[size_t(j)]);
        const double delta = d - mean;
        mean += delta / (j + 1);
        m2 += delta * (d - mean);
    }
    PilotBias out;
    out.mean = mean / shrink;
    out.se = std::sqrt(m2 / (pixels - 1) / pixels) / shrink;
    if (std::abs(out.mean) > kPilotBiasSigmas * out.se) out.bias2 = out.mean * out.mean - out.se * out.se;
    return out;
}

}  // namespace vpm
