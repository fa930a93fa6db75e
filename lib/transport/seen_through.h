#pragma once
// The sky or area light seen behind a camera segment whose in-scattering the march or the beam
// gathers apart (PhotonMapIntegrator::trace; docs/studies/scene_matrix.md section 11.11).
//
// Those gathers used the segment's free flight only to decide whether the light behind is seen
// (probability T): a Bernoulli trial of variance T (1 - T) L^2, which under a sky of radiance 1
// was 28x the collision gather's per-sample variance. Here it is weighed by T itself, from the
// media's exact optical depth (Medium::optical_depth_profile: closed forms in homogeneous media,
// the trilinear grid's cell by cell), so this part of the pixel has no variance at all. Nothing
// else lies on the segment: the light is its first surface hit (or it escapes). A profile stops at
// OpticalDepthProfile::kEnoughDepth (40): T is then e^-40 ~ 4e-18 instead of less.
#include "core/math.h"
#include "scene/media/optical_depth_profile.h"
#include "scene/scene.h"
#include "transport/mis.h"

namespace vpm {

// exp(-optical depth) over (0, t_end) of every medium; `profile` is scratch space.
double exact_transmittance(const Scene& scene, const Ray& ray, double t_end, OpticalDepthProfile& profile);

// The emission met at the end of the camera segment (hit: the first surface, an area light, when
// on_surface; else the ray escapes), weighted by `emission`, times the exact transmittance.
// `rays` counts the segment as tracked only where there is emission to weigh (the plan's work
// counts, render/plan/work_units.h, stay those of scenes without a sky or area light).
Rgb seen_through(const Scene& scene, const Ray& ray, bool on_surface, const SurfaceHit& hit, const EmissionWeighting& emission,
                 OpticalDepthProfile& profile, uint64_t& rays);
// The same with the media's optical depth over the segment already summed (the march's profiles:
// transport/march_points.h's for_each_march_point), the same value exact_transmittance gives.
Rgb seen_through_depth(const Scene& scene, const Ray& ray, bool on_surface, const SurfaceHit& hit,
                       const EmissionWeighting& emission, double depth, uint64_t& rays);

}  // namespace vpm
