#pragma once
// Light sources. Each light serves two integrators: next-event estimation from a point
// (sample_incident) and photon emission (sample_emission).
#include <memory>
#include <string>

#include "core/math.h"
#include "core/sampling/rng.h"
#include "scene/lights/direction_guide.h"

namespace vpm {

// Light arriving at a point: direction towards the light, distance to it (kInfinity for
// directional / environment) and radiance divided by the solid-angle pdf of the sample
// (for delta lights the incident irradiance-like weight I / d^2), and that solid-angle pdf for
// multiple importance sampling (0 for delta lights: no other strategy can find them).
struct LightSample {
    Vec3 wi = Vec3::UnitZ();
    double distance = kInfinity;
    Rgb weight = Rgb::Zero();
    double pdf = 0.0;
};

// A photon leaving a light: its ray and its power weight, normalised so that the mean of
// `power` over emissions equals the light's total power (the tracer divides by N).
struct EmissionSample {
    Ray ray;
    Rgb power = Rgb::Zero();
};

// A ray meeting an area light: the distance, the unit geometric normal turned to face the ray, and
// the radiance the light sends back along the ray (zero on the back of a one-sided emitter).
struct EmitterHit {
    double t = kInfinity;
    Vec3 normal = Vec3::UnitZ();
    Rgb radiance = Rgb::Zero();
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
    // Solid-angle pdf with which sample_incident(x) returns direction wi (0 for delta lights and
    // directions the light cannot send to x). The weight of the other strategy in MIS needs it.
    virtual double pdf_incident(const Vec3& x, const Vec3& wi) const { return 0.0; }
    // Lights at infinity emit photons over the silhouette of the bounds of what can be lit (media and
    // shapes; scene/lights/emission_bounds.h); they need those bounds.
    virtual void set_scene_bounds(const Bounds3& bounds) {}
    virtual bool at_infinity() const { return false; }
    // Lights that emit from one point (point, spot): that point, for strategies that place points
    // along a ray by their distance to it (transport/equiangular.h). false for every other light.
    virtual bool delta_position(Vec3& position) const { return false; }
    // Lights that a path cannot hit (a point, a spot, a direction): only next-event estimation finds
    // them, so light they send through mirrors and glass reaches no path-traced vertex.
    virtual bool delta() const { return false; }
    // They aim part of their photons at the region the camera sees (scene/camera_region.h) when it
    // is much smaller than those bounds (returns whether it does); other lights ignore it. Call
    // after set_scene_bounds.
    virtual bool set_emission_focus(const Bounds3& focus) { return false; }
    // Lights that emit from about one point over wide directions (a point light, a sphere light near
    // what it lights) can draw part of their photons from a guide over directions built from what
    // each direction reaches (scene/emission_guides.h). guide_origin gives that point and the distance
    // from it where photons start (the sphere's radius); false: this light takes no guide. Call after
    // set_scene_bounds.
    virtual bool guide_origin(Vec3& origin, double& start) const { return false; }
    // The solid-angle density of the light's own photon directions as seen from guide_origin
    // (0 where it sends none): the guide's weights are this times what a direction reaches.
    virtual double emission_direction_pdf(const Vec3& w) const { return 0.0; }
    // Emit `share` of the photons from `guide` (one-sample mixture with the light's own emission,
    // every photon weighted by the mixture's density: unbiased). An empty guide restores the default.
    virtual void set_emission_guide(std::shared_ptr<const DirectionGuide> guide, double share) {}
    // Area lights (quad, sphere) are opaque black geometry that emits: camera rays, scattered paths,
    // shadow rays to other lights and photons all stop on them (Scene::intersect, Scene::transmittance).
    // Closest hit in (epsilon, tmax), the epsilon keeping rays that leave the light from meeting it.
    virtual bool intersect(const Ray& ray, double tmax, EmitterHit& hit) const { return false; }
    // The box around an area light's surface; empty for lights that are not geometry.
    virtual Bounds3 bounds() const { return {}; }
    virtual std::string describe() const = 0;
};

}  // namespace vpm
