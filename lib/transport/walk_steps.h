#pragma once
// transport/: the steps every random walk in vpm takes, shared by the reference path tracer, the
// photon-map camera paths (render/) and the photon tracer (photon/), so that they sample the same
// scene in the same way. This layer sits on scene/ and below photon/ and render/:
//   walk_steps.h    next vertex (surface or medium collision), spawn ray, diffuse bounce, roulette
//   direct_light.h  next-event estimation with ratio-tracked transmittance
#include "core/sampling/sampling.h"
#include "scene/scene.h"

namespace vpm {

// Where a ray's walk goes next: the closest surface, and the first real medium collision before it.
struct PathVertex {
    SurfaceHit hit;
    bool on_surface = false;
    MediumEvent medium;   // set when a collision comes before the surface
    bool escaped() const { return !medium && !on_surface; }
};

// A ray leaving a surface hit, offset along the normal against self-intersection.
Ray spawn_ray(const SurfaceHit& hit, const Vec3& dir);

inline PathVertex next_vertex(const Scene& scene, const Ray& ray, Rng& rng) {
    PathVertex v;
    v.on_surface = scene.intersect(ray, kInfinity, v.hit);
    v.medium = scene.sample_medium(ray, v.on_surface ? v.hit.t : kInfinity, rng);
    return v;
}

// A cosine-distributed ray leaving a Lambertian hit (the weight reflectance is the caller's).
inline Ray diffuse_bounce(const SurfaceHit& hit, Rng& rng) {
    const double u1 = rng.uniform(), u2 = rng.uniform();
    return spawn_ray(hit, Frame(hit.normal).to_world(sample_cosine_hemisphere(u1, u2)).normalized());
}

// Russian roulette once a path has `vertices` >= rr_depth scattering events: survives with
// q = min(kRouletteMaxSurvival, max channel of throughput / radiance_scale) and divides by q; false
// when the path ends. radiance_scale is the product of the 1 / eta^2 factors a camera path's
// refractions put into its throughput (1 outside glass, 1 / 2.25 inside glass of ior 1.5): the
// roulette judges the path by the energy it carries, not by the radiance compression that its exit
// from the glass undoes (a path inside glass would otherwise be ended with probability 1 - 1 / 2.25
// at once and its survivors weigh 2.25x).
//
// The cap only makes sure a walk in a medium of albedo 1 ends. Every survival at the cap multiplies
// the throughput by 1 / cap, so after n collisions at albedo a the weight is (a / cap)^n with
// probability cap^n: the second moment grows as (a^2 / cap)^n, without bound for a > sqrt(cap).
// A cap close to 1 keeps that bounded for every albedo a real medium has: at 0.999 the weight stays
// below 1 / 0.999 up to albedo 0.9995 (the measurements behind it: docs/studies/heldout_scenes.md).
constexpr double kRouletteMaxSurvival = 0.999;
inline bool survive_roulette(Rgb& throughput, int vertices, int rr_depth, Rng& rng, double radiance_scale = 1.0) {
    if (vertices < rr_depth) return true;
    const double q = std::min(kRouletteMaxSurvival, throughput.maxCoeff() / radiance_scale);
    if (rng.uniform() >= q) return false;
    throughput /= q;
    return true;
}

}  // namespace vpm
