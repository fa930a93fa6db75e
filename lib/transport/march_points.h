#pragma once
// Where the march (photons.gather = "march") gathers along a camera segment: n stratified points
// with the free-flight density of one medium's exact extinction,
//
//   p(t) = sigma_t(t) exp(-tau(t)) / P,   P = 1 - exp(-tau(tmax)),
//
// by inverting its optical-depth profile (scene/media/optical_depth_profile.h). The estimate
// sum_j T(t_j) sigma_s(t_j) L(t_j) / (n p(t_j)) then weighs each point albedo P / n times the
// other media's transmittance: this medium's transmittance and extinction cancel exactly, so the
// weights are bounded by albedo P / n in any density field, where points placed by a majorant's
// free flight weighed up to e^(tau_majorant - tau) times that (issue 20 item 4).
#include <vector>

#include "core/math.h"
#include "core/rng.h"
#include "scene/media/medium.h"

namespace vpm {

// Fills ts with the points in increasing t (empty when the medium is not crossed) and returns P.
// Draws n uniforms from rng when P > 0, none otherwise. `profile` is scratch space.
double place_march_points(const Medium& medium, const Ray& ray, double tmax, int n, Rng& rng,
                          OpticalDepthProfile& profile, std::vector<double>& ts);

}  // namespace vpm
