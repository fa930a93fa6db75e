#pragma once
// Next-event estimation: one light sample per light, visibility and medium transmittance by
// ratio tracking. Shared by the reference path tracer and the photon-map renderer so that both
// compute single scattering and surface direct light identically.
#include "core/math.h"
#include "core/sampling/rng.h"
#include "scene/scene.h"
#include "transport/equiangular.h"

namespace vpm {

// `mis`: the walk goes on from this vertex by phase / BSDF sampling and counts the emission it
// meets with the power heuristic (transport/mis.h); each light sample is then weighted against the
// pdf of that sampling. false: every sample weighs 1 (the walk counts no emission after it).
// Area lights other than the sampled one block shadow rays.

// In-scattered radiance at a medium point x towards -ray_dir from all lights:
// sum_l phase(ray_dir -> wi reversed) * Li * T. Multiply by the scattering albedo outside.
// `at`: x is a point of a segment whose point and spot lights are also sampled equiangularly
// (transport/equiangular.h); their samples here weigh at->weight(light).
Rgb direct_light_in_medium(const Scene& scene, const Vec3& x, const Vec3& ray_dir, double g, Rng& rng, bool mis = false,
                           const SegmentPoint* at = nullptr);

// Reflected direct radiance of a Lambertian hit towards the viewer: reflectance/pi * Li cos * T.
Rgb direct_light_on_surface(const Scene& scene, const SurfaceHit& hit, Rng& rng, bool mis = false);

}  // namespace vpm
