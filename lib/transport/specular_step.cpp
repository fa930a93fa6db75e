#include "transport/specular_step.h"

#include "scene/materials/material.h"
#include "transport/walk_steps.h"

namespace vpm {

namespace {

bool sample_specular(const SurfaceHit& hit, Ray& ray, Transport mode, Rng& rng, Rgb& weight) {
    const double u1 = rng.uniform();
    MaterialSample s;
    if (!hit.specular->sample(ray.dir, hit.normal, hit.exiting, mode, u1, 0.0, 0.0, s)) return false;
    weight = s.weight;
    ray = spawn_ray(hit, s.dir);
    return true;
}

}  // namespace

bool camera_specular_step(const SurfaceHit& hit, Ray& ray, Rgb& throughput, EmissionWeighting& emission, int vertices,
                          int rr_depth, Rng& rng) {
    Rgb weight;
    if (!sample_specular(hit, ray, Transport::radiance, rng, weight)) return false;
    throughput *= weight;
    if ((throughput == 0.0).all()) return false;
    emission = EmissionWeighting::camera();
    return survive_roulette(throughput, vertices, rr_depth, rng);
}

bool photon_specular_step(const SurfaceHit& hit, Ray& ray, Rgb& power, Rng& rng) {
    Rgb weight;
    if (!sample_specular(hit, ray, Transport::power, rng, weight)) return false;
    const double q = weight.maxCoeff();
    if (q <= 0.0) return false;
    if (q < 1.0 && rng.uniform() >= q) return false;
    power *= weight / q;
    return true;
}

}  // namespace vpm
