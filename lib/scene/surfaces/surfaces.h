#pragma once
// The scene's opaque surfaces (triangle meshes from OBJ/PLY, quads, boxes) in one Embree 3
// scene. Only surfaces.cpp includes Embree; the rest of vpm sees this interface.
// Materials: Lambertian with an RGB reflectance in [0, 1], or black (reflectance 0: an occluder).
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "core/math.h"
#include "config/params.h"

namespace vpm {

class Light;
class Material;

struct SurfaceHit {
    double t = kInfinity;
    Vec3 position = Vec3::Zero();
    Vec3 normal = Vec3::UnitZ();   // unit geometric normal, flipped to face the incoming ray
    Rgb reflectance = Rgb::Zero(); // Lambertian albedo; zero for black and specular materials
    // Set when the material is specular (mirror, dielectric: scene/materials/material.h); walks
    // follow it with transport/specular_step.h. Null for Lambertian and black surfaces.
    const Material* specular = nullptr;
    bool exiting = false;          // the ray leaves the inside of a closed, oriented shape (dielectrics)
    // How far a ray leaving this hit starts off the surface: a bound on the rounding of position
    // across the surface, from the hit's own coordinates and shape (scene/surfaces/offsets.h).
    double epsilon = 0.0;
    // The closed dielectric shape hit, its index among the scene's dielectrics (Surfaces::
    // dielectric_shapes, scene/dielectric_regions.h); -1 for every other material.
    int dielectric = -1;
    // Set by Scene::intersect when the hit is an area light (black, so paths end there): the light
    // and the radiance it sends back along the ray.
    const Light* emitter = nullptr;
    Rgb emitted = Rgb::Zero();   // summed over coincident emitters (Scene::intersect)
    bool coincident_emitters = false;   // more than one area light at this point
};

// A closed dielectric shape, as the regions (scene/dielectric_regions.h) see it: a sphere
// (exact lens volumes) or a closed mesh (its bounds only; inside is read by ray parity).
struct DielectricShape {
    bool sphere = false;
    Vec3 center = Vec3::Zero();   // sphere
    double radius = 0.0;          // sphere
    Bounds3 bounds;
    size_t table = 0;             // the index of its [[shapes]] table
};

// Regions are masks of 64 bits, one per closed dielectric shape.
constexpr size_t kMaxDielectricShapes = 64;

class Surfaces {
public:
    // Builds one Embree device and scene from the [[shapes]] entries. Each entry's Params is
    // read fully (unknown keys are reported by finish()). Throws ConfigError / FileError, or
    // Error when Embree fails. An empty list gives an empty Surfaces and builds no device.
    // The keys of each shape type are documented at the top of surfaces.cpp.
    static std::unique_ptr<Surfaces> create(std::vector<Params>& shapes);
    // Number of Embree devices created in this process so far (for "built only what is used").
    static size_t devices_created();
    virtual ~Surfaces() = default;

    // Closest hit in (0, tmax), skipping the surface the ray starts on (offsets.h); false when none.
    virtual bool intersect(const Ray& ray, double tmax, SurfaceHit& hit) const = 0;
    // Any hit in (0, tmax), by the same rule.
    virtual bool occluded(const Ray& ray, double tmax) const = 0;
    virtual Bounds3 bounds() const = 0;
    virtual size_t triangle_count() const = 0;
    // The closed dielectric shapes, in the order of SurfaceHit::dielectric (at most
    // kMaxDielectricShapes: create() refuses more).
    virtual const std::vector<DielectricShape>& dielectric_shapes() const = 0;
    // Whether any shape is a mirror or glass (a specular material).
    virtual bool has_specular() const = 0;
    // Pairs ([[shapes]] table of a glass mesh, table of another triangle shape) that touch in one
    // plane (scene/surfaces/coplanar_contact.h): the scene warns of each.
    virtual std::vector<std::pair<size_t, size_t>> coplanar_glass_contacts() const = 0;
    virtual std::string describe() const = 0;
};

}  // namespace vpm
