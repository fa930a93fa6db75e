#pragma once
// Specular chains: a walk that meets a mirror or a dielectric (scene/materials/) goes on along the
// one direction the material samples, and estimates nothing there: next-event estimation cannot
// reach a light through a delta interface, and a photon map holds no photons on it. Camera paths of
// both integrators and the photon tracer take this step, so they sample the same chains.
//
// Camera paths carry radiance (a refraction scales it by 1 / eta^2); emission met after a
// specular event counts fully (EmissionWeighting::camera()): no light sample can have found it, so
// the power heuristic's other strategy has pdf 0. Photons carry power, which a refraction does not
// scale (scene/materials/material.h). The event counts as a scattering event for max_depth, Russian
// roulette and the photon tracer's max_bounces.
#include "core/sampling/rng.h"
#include "scene/materials/material.h"
#include "scene/scene.h"
#include "transport/mis.h"

namespace vpm {

// One specular event of a camera path at `hit` (hit.specular set), reached along `ray`: samples the
// material, multiplies `throughput` by its weight, sets `ray` to the ray leaving the surface and
// `emission` to full weight, then plays the walk's Russian roulette (transport/walk_steps.h) with
// `vertices` scattering events so far. false: the path ends (absorbed, or by the roulette).
// With `radiance_scale` (the product of the path's 1 / eta^2 factors so far), a refraction
// multiplies it by its own and the roulette judges throughput / radiance_scale (walk_steps.h);
// without it, the roulette judges the throughput as it is.
bool camera_specular_step(const SurfaceHit& hit, Ray& ray, Rgb& throughput, EmissionWeighting& emission, int vertices,
                          int rr_depth, Rng& rng, double* radiance_scale = nullptr);

// One branch of a split event (Material::both_events): event `s` taken for certain, so the
// throughput takes s.weight times its probability s.pdf; otherwise as camera_specular_step.
bool camera_specular_branch(const SurfaceHit& hit, const MaterialSample& s, Ray& ray, Rgb& throughput,
                            EmissionWeighting& emission, int vertices, int rr_depth, Rng& rng, double* radiance_scale);

// The photon's step: power times the material's weight over the survival probability q = its max
// channel (as on a Lambertian surface); false: absorbed.
bool photon_specular_step(const SurfaceHit& hit, Ray& ray, Rgb& power, Rng& rng);

}  // namespace vpm
