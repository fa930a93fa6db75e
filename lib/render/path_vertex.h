#pragma once
// The steps every random walk in vpm takes, shared by the reference path tracer, the photon-map
// camera paths and the photon tracer, so that they sample the same scene in the same way.
#include "core/sampling.h"
#include "render/direct_light.h"
#include "scene/scene.h"

namespace vpm {

// Where a ray's walk goes next: the closest surface, and the first real medium collision before it.
struct PathVertex {
    SurfaceHit hit;
    bool on_surface = false;
    MediumEvent medium;   // set when a collision comes before the surface
    bool escaped() const { return !medium && !on_surface; }
};

inline PathVertex next_vertex(const Scene& scene, const Ray& ray, Rng& rng) {
    PathVertex v;
    v.on_surface = scene.intersect(ray, kInfinity, v.hit);
    v.medium = scene.sample_medium(ray, v.on_surface ? v.hit.t : kInfinity, rng);
    return v;
}

// A cosine-distributed ray leaving a Lambertian hit (the weight reflectance is the caller's).
inline Ray diffuse_bounce(const SurfaceHit& hit, Rng& rng) {
    const double u1 = rng.uniform(), u2 = rng.uniform();
    return spawn_ray(hit.position, hit.normal, Frame(hit.normal).to_world(sample_cosine_hemisphere(u1, u2)).normalized());
}

// Russian roulette once a path has `vertices` >= rr_depth scattering events: survives with
// q = min(0.95, max channel of throughput) and divides by q; false when the path ends.
inline bool survive_roulette(Rgb& throughput, int vertices, int rr_depth, Rng& rng) {
    if (vertices < rr_depth) return true;
    const double q = std::min(0.95, throughput.maxCoeff());
    if (rng.uniform() >= q) return false;
    throughput /= q;
    return true;
}

}  // namespace vpm
