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
    explicit PathTracer(const Scene& scene, const WalkSettings& walk = {}) : scene_(scene), walk_(walk) {}
    Rgb radiance(const Ray& ray, Rng& rng) const override;
    std::string name() const override { return "path"; }
    bool stateless_passes() const override { return true; }   // nothing to prepare per pass

private:
    const Scene& scene_;
    WalkSettings walk_;
};

// The registry's reader: the walk keys of [render].
std::unique_ptr<IntegratorSettings> read_path_tracer_settings(Params& render, Params& root);

}  // namespace vpm
