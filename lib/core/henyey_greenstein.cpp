#include "core/henyey_greenstein.h"

#include <algorithm>

#include "core/sampling/turn_sincos.h"

namespace vpm {

namespace {
// Below this |g| the closed-form inversion divides by ~g and loses digits; the isotropic limit
// differs from HG there by O(g) in cos, which is far below double rounding at these g.
constexpr double kIsotropicG = 1e-5;
}  // namespace

double hg_eval(double cos_theta, double g) {
    // 1 + g^2 - 2 g mu written as (1-g)^2 + 2 g (1 - mu): no cancellation for mu -> 1, g -> 1.
    const double one_minus_g = 1.0 - g;
    const double denom = one_minus_g * one_minus_g + 2.0 * g * (1.0 - cos_theta);
    return kInv4Pi * (1.0 - g) * (1.0 + g) / (denom * std::sqrt(denom));
}

double hg_sample_cos(double g, double u) {
    if (std::abs(g) < kIsotropicG) return 1.0 - 2.0 * u;
    // Inverse CDF. s = (1 - g^2) / (1 - g + 2 g u); 1 - mu = (s - (1-g)) (s + (1-g)) / (2 g),
    // which keeps full precision in the forward peak where mu -> 1.
    const double one_minus_g = 1.0 - g;
    const double s = one_minus_g * (1.0 + g) / (one_minus_g + 2.0 * g * u);
    const double one_minus_mu = (s - one_minus_g) * (s + one_minus_g) / (2.0 * g);
    // Rounding can push mu a few ulps outside [-1, 1]; the clamp only removes rounding.
    return std::clamp(1.0 - one_minus_mu, -1.0, 1.0);
}

Vec3 hg_sample(const Vec3& d_in, double g, double u1, double u2) {
    const double mu = hg_sample_cos(g, u1);
    const double sin_theta = std::sqrt(std::max(0.0, (1.0 - mu) * (1.0 + mu)));
    const SinCos phi = sincos_turns(u2);   // azimuth 2 pi u2
    const Frame frame(d_in);
    return frame.to_world(Vec3(sin_theta * phi.cos, sin_theta * phi.sin, mu)).normalized();
}

}  // namespace vpm
