#include "transport/specular_step.h"

#include "scene/materials/material.h"
#include "transport/walk_steps.h"

namespace vpm {

namespace {

bool sample_specular(const SurfaceHit& hit, Ray& ray, Transport mode, Rng& rng, MaterialSample& s) {
    const double u1 = rng.uniform();
    if (!hit.specular->sample(ray.dir, hit.normal, hit.exiting, mode, u1, 0.0, 0.0, s)) return false;
    ray = spawn_ray(hit, s.dir);
    return true;
}

// The path after event s, its weight `weight`: throughput, emission and the roulette.
bool after_camera_event(const MaterialSample& s, const Rgb& weight, Rgb& throughput, EmissionWeighting& emission,
                        int vertices, int rr_depth, Rng& rng, double* radiance_scale) {
    throughput *= weight;
    if ((throughput == 0.0).all()) return false;
    emission = EmissionWeighting::camera();
    if (!radiance_scale) return survive_roulette(throughput, vertices, rr_depth, rng);
    *radiance_scale *= s.radiance_scale;
    return survive_roulette(throughput, vertices, rr_depth, rng, *radiance_scale);
}

}  // namespace

bool camera_specular_step(const SurfaceHit& hit, Ray& ray, Rgb& throughput, EmissionWeighting& emission, int vertices,
                          int rr_depth, Rng& rng, double* radiance_scale) {
    MaterialSample s;
    if (!sample_specular(hit, ray, Transport::radiance, rng, s)) return false;
    return after_camera_event(s, s.weight, throughput, emission, vertices, rr_depth, rng, radiance_scale);
}

bool camera_specular_branch(const SurfaceHit& hit, const MaterialSample& s, Ray& ray, Rgb& throughput,
                            EmissionWeighting& emission, int vertices, int rr_depth, Rng& rng, double* radiance_scale) {
    ray = spawn_ray(hit, s.dir);
    return after_camera_event(s, s.weight * s.pdf, throughput, emission, vertices, rr_depth, rng, radiance_scale);
}

bool photon_specular_step(const SurfaceHit& hit, Ray& ray, Rgb& power, Rng& rng) {
    MaterialSample s;
    if (!sample_specular(hit, ray, Transport::power, rng, s)) return false;
    const double q = s.weight.maxCoeff();
    if (q <= 0.0) return false;
    if (q < 1.0 && rng.uniform() >= q) return false;
    power *= s.weight / q;
    return true;
}

}  // namespace vpm
