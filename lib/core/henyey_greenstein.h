#pragma once
// Henyey-Greenstein phase function.
//
// Convention used everywhere in vpm: the phase function takes the cosine between the direction
// light travels before the scattering event (d_in) and the direction it travels after (d_out).
// g > 0 is forward scattering (d_out close to d_in). Normalised over the sphere: integral = 1.
#include "core/math.h"

namespace vpm {

// p(cos_theta) = (1 - g^2) / (4 pi (1 + g^2 - 2 g cos_theta)^{3/2}), |g| < 1.
double hg_eval(double cos_theta, double g);

// Samples d_out around d_in; returns d_out. The pdf equals hg_eval(dot(d_in, d_out), g), so the
// sampling weight phase/pdf is exactly 1 (that is what makes photon scattering weight-free).
Vec3 hg_sample(const Vec3& d_in, double g, double u1, double u2);

// The sampled cosine alone (exposed for tests).
double hg_sample_cos(double g, double u);

}  // namespace vpm
