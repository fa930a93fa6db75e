// vpm.load_config: a scene config (file, TOML or JSON text) with --set style overrides, read by
// exactly the code `vpm render` uses, so validation and messages are the tool's.
#include "config.h"

#include <sstream>

#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "bindings.h"
#include "core/progress.h"
#include "native_call.h"

namespace py = pybind11;

namespace vpm::python {

namespace {

Config load(const std::string& source, bool is_text, const std::string& name, const std::string& base_dir,
            const std::vector<std::string>& overrides) {
    Config c;
    call_native([&](const std::atomic<bool>&) {
        const Timer timer;
        auto doc = is_text ? parse_config(source, name, base_dir, overrides) : load_config(source, overrides);
        c.run = std::make_shared<const RunConfig>(RunConfig::build(doc));
        c.load_seconds = timer.seconds();
    });
    return c;
}

std::string resolved_json(const Config& c) {
    std::ostringstream s;
    s << toml::json_formatter(c.run->resolved);
    return s.str();
}

}  // namespace

void bind_config(py::module_& m) {
    py::class_<Config>(m, "Config", "A scene config, validated and resolved (every default filled in). Made by vpm.load_config.")
        .def_property_readonly("source", [](const Config& c) { return c.run->source_file; },
                               "The file it was read from (or the name given to text / a dict).")
        .def_property_readonly("toml", [](const Config& c) { return c.run->resolved_toml(); },
                               "The resolved config as TOML text (what the sidecar records).")
        .def_property_readonly("resolved", [](const Config& c) { return json_to_python(resolved_json(c)); },
                               "The resolved config as a dict.")
        .def_property_readonly("width", [](const Config& c) { return c.run->render.width; })
        .def_property_readonly("height", [](const Config& c) { return c.run->render.height; })
        .def_property_readonly("seed", [](const Config& c) { return c.run->render.seed; })
        .def_property_readonly("integrator", [](const Config& c) { return std::string(c.run->integrator->name); })
        .def_property_readonly("load_seconds", [](const Config& c) { return c.load_seconds; })
        .def("__repr__", [](const Config& c) {
            return "<vpm.Config " + c.run->source_file + ": " + c.run->integrator->name + ", " +
                   std::to_string(c.run->render.width) + "x" + std::to_string(c.run->render.height) + ">";
        });
    m.def("_load_config", &load, py::arg("source"), py::arg("is_text"), py::arg("name"), py::arg("base_dir"),
          py::arg("overrides"),
          "Reads a config file (is_text false) or config text (TOML, or JSON such as a run's sidecar) named `name`, "
          "relative paths from base_dir, with KEY=VALUE overrides validated like `vpm render --set`.");
}

}  // namespace vpm::python
