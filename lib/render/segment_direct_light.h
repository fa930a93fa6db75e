#pragma once
// Single scattering along a camera segment by next-event estimation at n stratified points per
// medium, for gathers that take only multiple scattering from the photon map along the whole
// segment (photons.gather = "beam"). The points follow the free-flight density of the medium's
// majorant mu, p(t) = mu(t) exp(-tau_mu(t)) / P with P = 1 - exp(-tau_mu(t_end)), like the march's
// (photon_map_integrator.cpp), and weigh T sigma_t / (mu e^-tau_mu) * P / n * albedo: unbiased
// for the integral of T sigma_s (f L_direct) over the segment, the albedo P / n exactly in
// homogeneous media. T is the product of independent transmittance estimates between points.
#include <cstdint>

#include "core/math.h"
#include "core/rng.h"
#include "scene/scene.h"

namespace vpm {

// `ray.dir` unit length; t_end may be kInfinity. `rays`: incremented by the tracked segments
// (transmittance intervals and shadow rays), for cost counts.
Rgb segment_direct_light(const Scene& scene, const Ray& ray, double t_end, int n, Rng& rng, uint64_t& rays);

}  // namespace vpm
