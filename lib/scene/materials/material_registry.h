#pragma once
// Materials by name. A [[shapes]] entry names its `material` (default "lambertian"); make_material
// dispatches to that material's factory, which reads its keys from the same table (each file
// documents its own):
//
//   material      file              keys
//   "lambertian"  lambertian.cpp    reflectance (number or [r,g,b] in [0,1], default 0.5)
//   "black"       black.cpp         none: reflects nothing (an occluder)
//   "mirror"      mirror.cpp        reflectance ([r,g,b] in [0,1], default 1)
//   "dielectric"  dielectric.cpp    ior (in (1, 4], default 1.5), transmittance ([r,g,b] in [0,1], default 1)
//
// Adding a material: one file with its Material class and factory, its keys in the table in
// material_registry.cpp, and one line there; README's [[shapes]] row names it
// (tests/tools/registry_docs_test.cpp fails until it does).
//
// What every material must meet (tests/scene/materials/material_test.cpp checks it for every entry):
// sample()'s weight is eval |cos| / pdf for smooth lobes and energy is not created (the mean
// weight in power transport is at most 1 per channel); eval is reciprocal (for a dielectric, up to
// the radiance's 1 / eta^2 at refraction); pdf integrates to 1 over the sphere for smooth lobes.
#include <memory>
#include <string>
#include <vector>

#include "config/params.h"
#include "scene/materials/material.h"

namespace vpm {

struct MaterialType {
    const char* name;
    std::shared_ptr<const Material> (*create)(Params& shape);   // reads its keys; the shape calls finish()
    std::vector<std::string> keys;                               // the keys it reads, for messages
};

const std::vector<MaterialType>& material_types();
std::vector<std::string> material_names();

// Reads `material` from a [[shapes]] table and builds it from that table's keys. A key that only
// another material takes (`ior` on a mirror) is one error naming the key, the material that takes
// it and the keys this one takes.
std::shared_ptr<const Material> make_material(Params& shape);

}  // namespace vpm
