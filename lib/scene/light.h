#pragma once
// Light sources. Each light serves two integrators: next-event estimation from a point
// (sample_incident) and photon emission (sample_emission).
#include <memory>
#include <string>

#include "core/math.h"
#include "core/rng.h"

namespace vpm {

// Light arriving at a point: direction towards the light, distance to it (kInfinity for
// directional / environment) and radiance divided by the solid-angle pdf of the sample
// (for delta lights the incident irradiance-like weight I / d^2).
struct LightSample {
    Vec3 wi = Vec3::UnitZ();
    double distance = kInfinity;
    Rgb weight = Rgb::Zero();
};

// A photon leaving a light: its ray and its power weight, normalised so that the mean of
// `power` over emissions equals the light's total power (the tracer divides by N).
struct EmissionSample {
    Ray ray;
    Rgb power = Rgb::Zero();
};

class Light {
public:
    virtual ~Light() = default;
    // Returns false when the light cannot reach x (behind a one-sided emitter, outside a spot cone).
    virtual bool sample_incident(const Vec3& x, Rng& rng, LightSample& out) const = 0;
    virtual EmissionSample sample_emission(Rng& rng) const = 0;
    // Total emitted power (W) into the scene.
    virtual Rgb power() const = 0;
    // Radiance seen by a ray that escapes to infinity in direction `dir` (environment only).
    virtual Rgb escaped_radiance(const Vec3& dir) const { return Rgb::Zero(); }
    // Lights at infinity emit photons over the silhouette of the bounds of what can be lit (media and
    // shapes; scene/emission_bounds.h); they need those bounds.
    virtual void set_scene_bounds(const Bounds3& bounds) {}
    virtual std::string describe() const = 0;
};

}  // namespace vpm
