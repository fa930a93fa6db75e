#include "scene/lights/light_registry.h"

#include <cmath>
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

void require_finite_power(const Params& p, const std::string& key, const Light& light, const std::string& why) {
    const Rgb power = light.power();
    if (power.allFinite() && std::isfinite(luminance(power))) return;
    std::ostringstream s;
    s << "the light's power " << format_rgb(power) << " W is not a finite double (" << why
      << "); make the light smaller or dimmer";
    p.fail(key, s.str());
}

std::string format_value(double v) {
    std::ostringstream s;
    s << v;
    return s.str();
}

std::string format_rgb(const Rgb& c) {
    std::ostringstream s;
    s << "[" << c[0] << ", " << c[1] << ", " << c[2] << "]";
    return s.str();
}

}  // namespace vpm
