#pragma once
// A scene built from a config text, as `vpm render` builds one from a file (the transport and render
// tests that trace single rays read their scenes this way). `name` only labels parse errors.
#include <memory>
#include <string>

#include "config/params.h"
#include "scene/scene.h"

namespace vpm::test {

inline std::unique_ptr<Scene> scene_from_config(const std::string& text, int width = 8, int height = 8,
                                                const std::string& name = "scene.toml") {
    auto doc = parse_config(text, name, ".");
    toml::table resolved;
    Params root(doc, &resolved);
    return Scene::build(root, width, height);
}

}  // namespace vpm::test
