#include "render/run/run_config.h"

#include "core/error.h"

namespace vpm {

RunConfig RunConfig::load(const std::string& path, const std::vector<std::string>& overrides) {
    return build(load_config(path, overrides));
}

RunConfig RunConfig::build(std::shared_ptr<const ConfigDocument> doc) {
    RunConfig c;
    c.source_file = doc->file;
    Params root(doc, &c.resolved);
    Params render = root.table("render");
    c.render = RenderSettings::read(render);
    const std::string chosen = render.choice("integrator", "path", integrator_names());
    for (const IntegratorType& type : integrator_types()) {
        c.settings.push_back(type.read(render, root));
        if (chosen == type.name) c.integrator = &type;
    }
    render.finish();
    c.scene = Scene::build(root, c.render.width, c.render.height);
    root.finish();
    return c;
}

const IntegratorSettings& RunConfig::integrator_settings() const { return settings_for(integrator->name); }

const IntegratorSettings& RunConfig::settings_for(const std::string& name) const {
    const auto& types = integrator_types();
    for (size_t i = 0; i < types.size(); ++i)
        if (name == types[i].name) return *settings.at(i);
    throw Error("no integrator named '" + name + "'");
}

}  // namespace vpm
