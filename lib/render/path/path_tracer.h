#pragma once
// The reference integrator: an unbiased volumetric path tracer over the same scene objects as
// the photon-map renderer. Delta tracking for collisions (the collision weight is the albedo),
// next-event estimation to every light at every vertex with ratio-tracked transmittance, HG
// phase sampling, Lambertian surfaces, Russian roulette from rr_depth on. max_depth < 0 means
// unlimited path length, which is what makes it unbiased.
//
// Mirrors and glass (transport/specular_step.h): the path follows the material's sampled direction
// and NEE is not taken there. Light reaching a diffuse or medium vertex through glass or by a
// mirror is found only when the walk's own phase / BSDF sample runs the chain into an area light or
// the sky (counted with weight 1); delta lights (point, spot, directional) seen through a specular
// chain contribute nothing: that light, the caustic, is the photon map's (docs/caustics.md).
//
// Emission is counted once: the camera sees area lights and the environment directly; after a
// vertex, light sampling and the walk's phase / BSDF sampling are combined by the power heuristic
// (render.mis = true, transport/mis.h), or light sampling alone counts (render.mis = false).
#include <memory>

#include "render/integrator.h"
#include "scene/scene.h"
#include "transport/walk_settings.h"

namespace vpm {

class Params;

class PathTracer : public Integrator {
public:
    // sized_passes: under render.time_limit with render.passes unset, every pass holds one sample
    // per pixel, so that the first pass fits the limit wherever one sample per pixel does and the
    // limit, not spp, says how many are taken (a constant: the same passes on any machine).
    PathTracer(const Scene& scene, const WalkSettings& walk = {}, bool sized_passes = false)
        : scene_(scene), walk_(walk), sized_passes_(sized_passes) {}
    void prepare(const PassContext& context, RunStats& stats) override;
    Rgb radiance(const Ray& ray, Rng& rng) const override;
    std::string name() const override { return "path"; }
    bool stateless_passes() const override { return true; }   // nothing to prepare per pass
    int samples_per_pass(int configured) const override { return sized_passes_ ? 1 : configured; }

private:
    const Scene& scene_;
    WalkSettings walk_;
    bool sized_passes_ = false;
};

// The registry's reader: the walk keys of [render].
std::unique_ptr<IntegratorSettings> read_path_tracer_settings(Params& render, Params& root);

}  // namespace vpm
