#include "render/run/run_config.h"

#include "core/error.h"

namespace vpm {

namespace {

// The dotted paths of the values in `resolved` that `given` (the document, or its part at the same
// path; null: absent) does not hold, appended to `out`.
void collect_defaulted(const toml::node& resolved, const toml::node* given, const std::string& path,
                       std::vector<std::string>& out) {
    if (const toml::table* t = resolved.as_table()) {
        const toml::table* g = given ? given->as_table() : nullptr;
        for (const auto& [key, value] : *t)
            collect_defaulted(value, g ? g->get(key) : nullptr, path + std::string(key.str()) + ".", out);
    } else if (const toml::array* a = resolved.as_array(); a && a->is_array_of_tables()) {
        const toml::array* g = given ? given->as_array() : nullptr;
        for (size_t i = 0; i < a->size(); ++i)
            collect_defaulted(*a->get(i), g ? g->get(i) : nullptr, path + std::to_string(i) + ".", out);
    } else if (!given) {
        out.push_back(path.substr(0, path.size() - 1));
    }
}

}  // namespace

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
    collect_defaulted(c.resolved, &doc->root, "", c.defaulted);
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
