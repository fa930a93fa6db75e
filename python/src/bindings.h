#pragma once
// The parts of the _vpm extension module, one concept per file; module.cpp calls each.
#include <pybind11/pybind11.h>

namespace vpm::python {

void bind_config(pybind11::module_& m);        // config.cpp: load_config, Config
void bind_render(pybind11::module_& m);        // render.cpp: render, RenderResult, read_exr
void bind_photon_map(pybind11::module_& m);    // photon_map.cpp: trace_photons, PhotonMap
void bind_analysis(pybind11::module_& m);      // analysis.cpp: study, sweep
void bind_compare(pybind11::module_& m);       // compare.cpp: compare, luminance

// JSON text -> Python objects (json.loads): how records and resolved configs reach Python.
pybind11::object json_to_python(const std::string& text);

}  // namespace vpm::python
