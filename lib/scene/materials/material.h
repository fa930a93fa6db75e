#pragma once
// The scattering of a surface, chosen per [[shapes]] entry by `material` (material_registry.h).
//
// Directions follow the walks' convention: `d` is the direction the ray (camera path or photon)
// travels when it meets the surface, `n` the unit geometric normal turned to face it (n . d < 0),
// and a sampled `dir` is the direction the walk travels on. `exiting` says the ray travels from the
// inside of a closed shape to its outside (dielectrics need it; the others ignore it).
//
// Diffuse materials (lambertian, black) keep the walks' own Lambertian step (transport/walk_steps.h)
// and are described to them by diffuse_reflectance() alone; specular materials (mirror,
// dielectric) scatter into discrete directions, which next-event estimation cannot reach, and are
// followed by transport/specular_step.h. Every material also gives eval / pdf / sample, so that
// the material tests check all of them in one way (tests/scene/materials/).
#include <string>

#include "core/math.h"

namespace vpm {

// What a walk carries: radiance (camera paths; a refraction scales it by 1 / eta^2, eta the index
// ratio of the side the ray enters over the side it leaves) or power (photons; not scaled: a
// refracted beam keeps its flux times 1 - F, though its solid angle shrinks or widens).
enum class Transport { radiance, power };

struct MaterialSample {
    Vec3 dir = Vec3::UnitZ();   // the direction travelled on, unit length
    Rgb weight = Rgb::Zero();   // f |cos| / pdf for smooth lobes; the event's factor over its probability for delta ones
    double pdf = 0.0;           // solid-angle pdf (smooth), or the discrete probability of this event (delta)
    bool delta = false;
    bool transmitted = false;   // crossed the surface (refraction)
    double radiance_scale = 1.0;   // the part of weight that radiance alone takes: 1 / eta^2 on a refraction, else 1
};

class Material {
public:
    virtual ~Material() = default;
    virtual std::string name() const = 0;
    virtual std::string describe() const = 0;
    // The Lambertian albedo the walks use (zero for black and for specular materials).
    virtual Rgb diffuse_reflectance() const { return Rgb::Zero(); }
    // Scatters only into discrete directions (mirror, dielectric).
    virtual bool specular() const { return false; }
    // Needs the shape to be closed and consistently oriented, so that `exiting` is defined.
    virtual bool needs_closed_shape() const { return false; }
    // The BSDF value f(d -> dir) of the smooth part (0 for delta materials) and the solid-angle pdf
    // with which sample() takes dir (0 for delta materials).
    virtual Rgb eval(const Vec3& d, const Vec3& n, bool exiting, const Vec3& dir, Transport mode) const = 0;
    virtual double pdf(const Vec3& d, const Vec3& n, bool exiting, const Vec3& dir) const = 0;
    // Draws the next direction from u1, u2, u3 in [0, 1); false when nothing leaves (black).
    virtual bool sample(const Vec3& d, const Vec3& n, bool exiting, Transport mode, double u1, double u2, double u3,
                        MaterialSample& out) const = 0;
    // Both events of a delta material that reflects and refracts at this incidence (a dielectric
    // short of total internal reflection): out[0] the reflection, out[1] the refraction, each as
    // sample() gives it (pdf: the event's probability, the two summing to 1). false: one event only.
    virtual bool both_events(const Vec3&, const Vec3&, bool, Transport, MaterialSample[2]) const { return false; }
};

}  // namespace vpm
