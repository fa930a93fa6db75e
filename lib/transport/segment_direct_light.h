#pragma once
// Single scattering along a camera segment by next-event estimation at n stratified points per
// medium, for gathers that take only multiple scattering from the photon map along the whole
// segment (photons.gather = "beam"). The points are the march's (transport/march_points.h: the
// free flight of the medium's exact extinction), each weighing albedo P / n times the other media's
// transmittance: unbiased for the integral of T sigma_s (f L_direct) over the segment.
#include <cstdint>

#include "core/math.h"
#include "core/sampling/rng.h"
#include "scene/scene.h"

namespace vpm {

// `ray.dir` unit length; t_end may be kInfinity. `rays`: incremented by the tracked segments
// (transmittance intervals and shadow rays), for cost counts. `equiangular` (render.equiangular):
// point and spot lights are also sampled equiangularly along the segment, the points' NEE to them
// weighted against it by the balance heuristic with the points' density (transport/equiangular.h).
Rgb segment_direct_light(const Scene& scene, const Ray& ray, double t_end, int n, Rng& rng, uint64_t& rays,
                         bool equiangular = false);

}  // namespace vpm
