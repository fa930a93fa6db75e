#pragma once
// A light built by the registry from the first [[lights]] table of a config text, as a scene
// would build it (the lights tests read their cases this way).
#include <memory>
#include <string>

#include "scene/lights/light_registry.h"
#include "config/params.h"

namespace vpm::test {

inline std::unique_ptr<Light> light_from(const std::string& text) {
    auto doc = parse_config(text, "light.toml", ".");
    toml::table resolved;
    Params root(doc, &resolved);
    auto tables = root.tables("lights");
    return make_light(tables.at(0));
}

}  // namespace vpm::test
