#pragma once
// Single scattering at a photon-map vertex, estimated as the path tracer does (docs/studies/scene_matrix.md section 11.11).
//
// Where the map's estimate ends the camera path, the map holds only light that scattered before
// (direct = "nee"), so the unscattered light comes from NEE alone. Light sampling alone is a worse
// estimator than the path tracer's light sampling + bounce under the power heuristic wherever a
// bounce can find the light (environment and area lights): 2x the per-sample variance in the
// matrix's environment-lit dense sphere, 1.6x in the thin blob. So both strategies are taken here
// too: NEE weighted by the power heuristic, and one phase-sampled direction whose emission is
// weighted likewise and multiplied by the transmittance estimate to it (not a free flight: no
// Bernoulli noise). The weights sum to one for every direction: unbiased for the same integral.
// Delta lights (point, spot, directional) are found by NEE only, so scenes with only those keep
// plain NEE and draw the same random numbers as before.
//
// Where the path goes on past the vertex (too few photons within photons.max_radius_mfp, a starved
// map, the auto plan's "continue"), it is the path tracer's own vertex: NEE under the power heuristic
// and the bounce's emission weighted likewise (continued_emission). Before, such paths weighed NEE
// 1 and counted no emission they met: 4.3x the path tracer's per-sample variance under a sky.
#include "core/math.h"
#include "core/sampling/rng.h"
#include "scene/scene.h"
#include "transport/equiangular.h"
#include "transport/mis.h"

namespace vpm {

// Whether a phase-sampled bounce can meet emission: an area light, or a light at infinity whose
// NEE samples carry a solid-angle pdf (an environment; a directional light is a delta).
bool bounces_find_lights(const Scene& scene);

// Single scattering at medium point x towards -ray_dir (phase g), both strategies (above).
// `rays` counts the tracked segments (NEE's shadow rays and the bounce's). `at`: as for
// direct_light_in_medium (point and spot lights also sampled equiangularly along the segment).
Rgb single_scattering_both_strategies(const Scene& scene, const Vec3& x, const Vec3& ray_dir, double g, Rng& rng,
                                      uint64_t& rays, const SegmentPoint* at = nullptr);

// How emission met after a path continues from x along wo (sampled by the phase from ray_dir) counts:
// MIS-weighted when render.mis, its NEE having been weighted too; else 0.
EmissionWeighting continued_emission(bool mis, const Vec3& x, const Vec3& ray_dir, const Vec3& wo, double g);

}  // namespace vpm
