#pragma once
// A config file read whole: what is seen (Scene), how the image is made (RenderSettings) and the
// settings of every registered integrator, of which render.integrator picks one. Every value
// used, defaults included, is in `resolved`, which the run record writes back as the config;
// `defaulted` names the values in it that the document left unset, so that the record renders
// again as the document did (a default written back would read as a pin: docs/integrator_choice.md).
#include <memory>
#include <string>
#include <vector>

#include "render/integrator.h"
#include "render/integrator_registry.h"
#include "render/run/render_settings.h"
#include "config/params.h"
#include "scene/scene.h"

namespace vpm {

struct RunConfig {
    std::string source_file;
    toml::table resolved;
    std::vector<std::string> defaulted;   // dotted paths ("render.spp", "media.0.g") of resolved values not in the document
    RenderSettings render;
    std::unique_ptr<Scene> scene;
    const IntegratorType* integrator = nullptr;                  // the chosen entry
    std::vector<std::unique_ptr<IntegratorSettings>> settings;   // one per registry entry, same order

    // Reads `path` with --set style overrides; throws ConfigError / FileError.
    static RunConfig load(const std::string& path, const std::vector<std::string>& overrides = {});
    static RunConfig build(std::shared_ptr<const ConfigDocument> doc);

    // The chosen integrator's settings, and any registered integrator's by name (throws Error).
    const IntegratorSettings& integrator_settings() const;
    const IntegratorSettings& settings_for(const std::string& integrator_name) const;
    // Builds the chosen integrator for this config's scene.
    std::unique_ptr<Integrator> create_integrator() const { return integrator_settings().create(*scene); }
    std::string resolved_toml() const { return to_toml_string(resolved); }
};

}  // namespace vpm
