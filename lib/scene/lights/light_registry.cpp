#include "scene/lights/light_registry.h"

#include <sstream>

#include "core/registry.h"

namespace vpm {

// Each type's factory, defined in its own file.
std::unique_ptr<Light> make_point_light(Params&);
std::unique_ptr<Light> make_spot_light(Params&);
std::unique_ptr<Light> make_directional_light(Params&);
std::unique_ptr<Light> make_quad_light(Params&);
std::unique_ptr<Light> make_sphere_light(Params&);
std::unique_ptr<Light> make_environment_light(Params&);

const std::vector<LightType>& light_types() {
    static const std::vector<LightType> types = {
        {"point", make_point_light},
        {"spot", make_spot_light},
        {"directional", make_directional_light},
        {"quad", make_quad_light},
        {"sphere", make_sphere_light},
        {"environment", make_environment_light},
    };
    return types;
}

std::vector<std::string> light_names() { return registry_names(light_types()); }

std::unique_ptr<Light> make_light(Params& p) {
    const std::string type = p.choice("type", light_names());
    std::unique_ptr<Light> light = registry_find(light_types(), type)->create(p);
    p.finish();
    return light;
}

std::string format_rgb(const Rgb& c) {
    std::ostringstream s;
    s << "[" << c[0] << ", " << c[1] << ", " << c[2] << "]";
    return s.str();
}

}  // namespace vpm
