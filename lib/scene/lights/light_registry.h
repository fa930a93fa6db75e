#pragma once
// Light types by name. Each [[lights]] table names its `type`; make_light dispatches to that
// type's factory, which reads the table's keys (each *_light.cpp documents its own):
//
//   type          file                     keys
//   "point"       point_light.cpp          position, intensity
//   "spot"        spot_light.cpp           position, look_at, intensity, cone_angle
//   "directional" directional_light.cpp    direction, irradiance
//   "quad"        quad_light.cpp           center, u, v, radiance, two_sided
//   "sphere"      sphere_light.cpp         center, radius, radiance
//   "environment" environment_light.cpp    radiance, or file (lat-long EXR), scale, rotate_y
//
// Adding a light type: one file with its Light class and factory, and one line in the table in
// light_registry.cpp (with its declaration beside it); docs/config.md's [[lights]] row names it
// (tests/tools/registry_docs_test.cpp fails until it does).
//
// What every light must meet (Scene::build and tests/scene/registry_test.cpp check it):
// - power() is the mean of sample_emission's `power` (the test estimates it by Monte Carlo for
//   every registered type), finite and representable: a factory refuses values whose power or
//   pdf overflow, naming the key.
// - sample_emission starts photons on the light (or, for lights at infinity, on the silhouette of
//   the scene bounds set by set_scene_bounds, which Scene::build guarantees finite).
// - sample_incident's weight is radiance / pdf with pdf the solid-angle density pdf_incident
//   returns for that direction (0 for delta lights); one-sided emitters emit on the side their
//   file documents and return false / zero behind it.
// - bounds() holds the whole emitting surface of an area light (empty for the others): it is
//   part of what can be lit and of what blocks light.
#include <memory>
#include <string>
#include <vector>

#include "scene/lights/light.h"
#include "config/params.h"

namespace vpm {

struct LightType {
    const char* name;
    std::unique_ptr<Light> (*create)(Params& table);   // reads its keys; the caller calls finish()
};

// The registered types, in registry order, and their names (core/registry.h).
const std::vector<LightType>& light_types();
std::vector<std::string> light_names();

// Reads `type`, builds that light from the rest of the table and reports unknown keys.
std::unique_ptr<Light> make_light(Params& table);

// The allowed range of every emission value a light reads (radiance, intensity, irradiance, an
// environment map's scale times its brightest texel): [0, 1e30]. Images are float32 (largest 3.4e38),
// and a render multiplies emission by sample counts, 1 / distance^2 and 1 / V(r_k): 1e30 leaves eight
// orders of magnitude for them, and a scene scaled as a whole by s = 1e6 scales intensities by s^2 =
// 1e12 only. Larger values gave NaN/Inf images or a photon pass that stopped on a NaN weight.
constexpr double kMaxEmission = 1e30;
inline Range emission_range() { return Range::closed(0.0, kMaxEmission); }

// Refuses (naming `key` of `p`) a light whose total power is not a finite double, e.g. a sphere or
// quad so large that its area overflows; called where the power is known (for lights at infinity,
// once the scene's bounds are set).
void require_finite_power(const Params& p, const std::string& key, const Light& light, const std::string& why);

// A number for messages (%g with 6 digits).
std::string format_value(double v);
// "[r, g, b]" for describe() lines.
std::string format_rgb(const Rgb& c);

}  // namespace vpm
