// _vpm: the compiled part of the vpm Python package (python/vpm/__init__.py is the public face).
// Errors: vpm's own exceptions become vpm.Error (ConfigError, FileError below it) carrying the
// tool's one-line message unchanged, the text `vpm render` prints after "error: ".
#include <pybind11/pybind11.h>

#include "bindings.h"
#include "core/build_info.h"
#include "core/error.h"

namespace py = pybind11;

namespace vpm::python {

py::object json_to_python(const std::string& text) {
    return py::module_::import("json").attr("loads")(py::str(text));
}

}  // namespace vpm::python

PYBIND11_MODULE(_vpm, m) {
    m.doc() = "Native core of the vpm package: the vpm library (render, photon maps, study, sweep). Use `import vpm`.";
    // Translators run newest first: the subclasses are registered after their base.
    static py::exception<vpm::Error> error(m, "Error", PyExc_RuntimeError);
    static py::exception<vpm::ConfigError> config_error(m, "ConfigError", error.ptr());
    static py::exception<vpm::FileError> file_error(m, "FileError", error.ptr());
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const vpm::ConfigError& e) {
            config_error(e.what());
        } catch (const vpm::FileError& e) {
            file_error(e.what());
        } catch (const vpm::Error& e) {
            error(e.what());
        }
    });
    m.attr("__version__") = vpm::vpm_version();
    m.attr("git_revision") = vpm::git_revision();
    vpm::python::bind_config(m);
    vpm::python::bind_render(m);
    vpm::python::bind_photon_map(m);
    vpm::python::bind_analysis(m);
    vpm::python::bind_compare(m);
}
