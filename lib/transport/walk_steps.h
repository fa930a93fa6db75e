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
// q = min(kRouletteMaxSurvival, max channel of throughput) and divides by q; false when the path ends.
//
// The cap only makes sure a walk in a medium of albedo 1 ends. Every survival at the cap multiplies
// the throughput by 1 / cap, so after n collisions at albedo a the weight is (a / cap)^n with
// probability cap^n: the second moment grows as (a^2 / cap)^n, without bound for a > sqrt(cap).
// With a cap of 0.95 that was every albedo above 0.975: deep walks in dense albedo-0.99 media came
// back with weights of 700 at 165 collisions (bench/heldout/h25), and the path tracer's relative
// RMSE there was 0.12-0.16 at 4 s against 0.093 with 0.999, at 1.7x the time per sample
// (docs/studies/heldout_scenes.md section 31). At 0.999 the weight stays below 1 / 0.999 up to albedo 0.9995.
constexpr double kRouletteMaxSurvival = 0.999;
inline bool survive_roulette(Rgb& throughput, int vertices, int rr_depth, Rng& rng) {
    if (vertices < rr_depth) return true;
    const double q = std::min(kRouletteMaxSurvival, throughput.maxCoeff());
    if (rng.uniform() >= q) return false;
    throughput /= q;
    return true;
}

}  // namespace vpm
