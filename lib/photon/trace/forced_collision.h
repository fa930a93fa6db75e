#pragma once
// Forced collisions for photons (photons.forced_collisions): in a thin medium most photons cross it
// without a collision and store nothing (588 photons stored of 1e5 emitted in a blob under
// a quad light, the kNN balls spanning the blob and the image +7% high from smoothing). A forced step
// computes the exact optical depth tau of the photon's segment (Medium::optical_depth_profile) and
// collides inside it when tau <= kForcedMaxDepth, at a distance drawn from the free-flight density conditioned on a
// collision; the photon's power is multiplied by 1 - exp(-tau), and the share exp(-tau) is what the
// analog walk would have carried past the medium (escaped, or absorbed by a black surface or an
// emitter). The expected power at every collision is the analog walk's: unbiased, with every photon
// that enters the medium storing photons. A weight window keeps the powers from dwindling: below
// kForcedWindow of the photon's emitted power it plays Russian roulette up to that level.
//
// It applies where it is exact and cheap to state: one medium in the scene, and segments that end
// in the medium's exit, an emitter or a black surface (a reflecting surface, Lambertian, mirror or
// glass, keeps the analog step, which decides between collision and reflection by one free flight).
#include "core/sampling/rng.h"
#include "scene/scene.h"
#include "transport/walk_steps.h"

namespace vpm {

// Segments thicker than this take the analog free flight (from the same exact profile): forcing
// them gains less than 1 / (1 - exp(-1)) = 1.6x collisions per step, and in dense media it turned
// photons about to leave into long chains of light ones (a cube 40 mfp wide at albedo 0.99 when
// every segment was forced: 22 collisions per photon against 8.4, the trace 6x dearer).
constexpr double kForcedMaxDepth = 1.0;

// Powers below this fraction of the emitted one play roulette up to it (bounded weights in the map).
constexpr double kForcedWindow = 1.0 / 64.0;

struct ForcedStep {
    PathVertex vertex;            // the collision (vertex.medium set), or where tau = 0 the pass
    double transmittance = 1.0;   // forced: exp(-tau) of the whole segment, the share that passes it; 0: analog
    bool forced = true;           // false: a reflecting surface ended the segment, the analog step was taken
};

// Whether forced steps can apply in this scene at all (one medium).
bool forced_collisions_possible(const Scene& scene);

// One step along ray: forced where it applies, else (a reflecting surface ends the segment) the
// analog step, as next_vertex takes it with the same rng and the same surface hit.
ForcedStep forced_step(const Scene& scene, const Ray& ray, Rng& rng, OpticalDepthProfile& scratch);

}  // namespace vpm
