#include "scene/materials/material_registry.h"

#include "core/registry.h"

namespace vpm {

// Each material's factory, defined in its own file.
std::shared_ptr<const Material> make_lambertian_material(Params&);
std::shared_ptr<const Material> make_black_material(Params&);
std::shared_ptr<const Material> make_mirror_material(Params&);
std::shared_ptr<const Material> make_dielectric_material(Params&);

const std::vector<MaterialType>& material_types() {
    static const std::vector<MaterialType> types = {
        {"lambertian", make_lambertian_material, {"reflectance"}},
        {"black", make_black_material, {}},
        {"mirror", make_mirror_material, {"reflectance"}},
        {"dielectric", make_dielectric_material, {"ior", "transmittance"}},
    };
    return types;
}

std::vector<std::string> material_names() { return registry_names(material_types()); }

std::shared_ptr<const Material> make_material(Params& shape) {
    const std::string name = shape.choice("material", "lambertian", material_names());
    const MaterialType* type = registry_find(material_types(), name);
    for (const MaterialType& other : material_types())
        for (const std::string& key : other.keys) {
            if (!shape.has(key)) continue;
            bool own = false;
            for (const std::string& k : type->keys) own = own || k == key;
            if (own) continue;
            const std::string takes = type->keys.empty() ? "no keys" : "only " + registry_list(type->keys);
            shape.fail(key, "a key of material = \"" + std::string(other.name) + "\"; material = \"" + name + "\" takes " + takes);
        }
    return type->create(shape);
}

}  // namespace vpm
