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
// light_registry.cpp (with its declaration beside it).
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

// The registered types, in registry order.
const std::vector<LightType>& light_types();

// Reads `type`, builds that light from the rest of the table and reports unknown keys.
std::unique_ptr<Light> make_light(Params& table);

// "[r, g, b]" for describe() lines.
std::string format_rgb(const Rgb& c);

}  // namespace vpm
