// vpm.render: one run of a config, as `vpm render` does it (lib/render/run/run.h), returning the image
// as a NumPy view on the run's own pixels (no copy), the typed statistics as a dict, and save()
// writing the tool's three files (EXR, PNG preview, JSON sidecar) with the tool's guarantees.
#include <iostream>
#include <memory>
#include <optional>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <tbb/info.h>

#include "bindings.h"
#include "config.h"
#include "native_call.h"
#include "core/progress.h"
#include "render/run/image_io.h"
#include "render/run/run.h"
#include "render/run/run_outputs.h"
#include "render/photon_map/photon_map_stats.h"

namespace py = pybind11;

namespace vpm::python {

namespace {

struct RenderResult {
    std::shared_ptr<const RunConfig> config;
    std::shared_ptr<RunResult> run;
    double load_seconds = 0.0;
    double seconds = 0.0;   // wall time of the run (vpm::run: every phase, the plan's pilot included)
    int threads = 0;
};

// The threads the run may use: `threads` if given, else render.threads, 0 meaning all cores (as the tool).
int thread_count(const RunConfig& config, std::optional<int> threads) {
    if (threads) check_threads(*threads);
    const int n = threads ? *threads : config.render.threads;
    return n > 0 ? n : tbb::info::default_concurrency();
}

RenderResult render(const Config& config, std::optional<int> threads, bool progress, bool log, uint64_t stream_offset) {
    RenderResult r;
    r.config = config.run;
    r.load_seconds = config.load_seconds;
    r.threads = thread_count(*config.run, threads);
    r.run = std::make_shared<RunResult>();
    call_native(
        [&](const std::atomic<bool>& interrupted) {
            RunOptions options;
            options.progress = progress;
            options.log = log ? &std::cerr : nullptr;
            options.stream_offset = stream_offset;
            options.cancelled = [&interrupted] { return interrupted.load(); };
            const Timer timer;
            *r.run = vpm::run(*config.run, options);
            r.seconds = timer.seconds();
        },
        r.threads);
    return r;
}

// A view of the run's pixels: H x W x 3 float32, kept alive by the result object.
py::array image_view(py::object self) {
    RenderResult& r = self.cast<RenderResult&>();
    const Image& im = r.run->image;
    return py::array_t<float>({size_t(im.height), size_t(im.width), size_t(3)}, im.rgb.data(), self);
}

void save(RenderResult& r, const std::string& path) {
    call_native([&](const std::atomic<bool>&) {
        check_run_outputs(path);
        r.run->record.phase("load", r.load_seconds);
        r.run->record.set("threads", r.threads);
        r.run->record.set("config.render.output", path);
        write_run_outputs(path, *r.run, r.config->render.exposure);
    });
}

py::array read_exr_array(const std::string& path) {
    auto image = std::make_unique<Image>();
    call_native([&](const std::atomic<bool>&) { *image = read_exr(path); });
    const Image* im = image.get();
    py::capsule owner(image.release(), [](void* p) { delete static_cast<Image*>(p); });
    return py::array_t<float>({size_t(im->height), size_t(im->width), size_t(3)}, im->rgb.data(), owner);
}

}  // namespace

void bind_render(py::module_& m) {
    py::class_<RenderResult>(m, "RenderResult", "What vpm.render returns: the image, the run's statistics and its record.")
        .def_property_readonly("image", &image_view,
                               "Linear RGB radiance, float32 array of shape (height, width, 3), row 0 at the top: "
                               "a view on the run's pixels (no copy); save() writes these pixels.")
        .def_property_readonly("_stats_json", [](const RenderResult& r) {
            RunRecord stats;
            write_run_stats(r.run->stats, stats);
            return stats.dump();
        })
        .def_property_readonly("_record_json", [](const RenderResult& r) { return r.run->record.dump(); })
        .def_property_readonly("threads", [](const RenderResult& r) { return r.threads; })
        .def_property_readonly("seconds", [](const RenderResult& r) { return r.seconds; },
                               "Wall time of the run in seconds (every phase, the plan's pilot included; not the config's load).")
        .def_property_readonly("integrator_used", [](const RenderResult& r) { return r.run->stats.integrator_used; },
                               "The integrator that rendered: \"photon_map\" or \"path\" (for render.integrator = "
                               "\"auto\", its plan's choice).")
        .def_property_readonly("gather_used", [](const RenderResult& r) { return r.run->stats.gather_used.value_or("none"); },
                               "The photon map's gather (\"collision\", \"march\", \"threshold\", \"beam\"); "
                               "\"none\" without a map.")
        .def_property_readonly("map_estimates", [](const RenderResult& r) { return r.run->stats.map_estimates.value_or(0); },
                               "Estimates the camera passes took from a photon map (0: the map was not used).")
        .def_property_readonly("passes", [](const RenderResult& r) { return r.run->stats.pass_count(); },
                               "Passes the run rendered.")
        .def_property_readonly("spp_per_pass", [](const RenderResult& r) { return r.run->stats.pass_summary.spp; },
                               "Samples per pixel of each pass.")
        .def_property_readonly("photons_traced", [](const RenderResult& r) -> uint64_t {
            const auto& l = PhotonMapStats::of(r.run->stats).photon_ledger;
            return l ? l->pass_maps + l->pilot_only + l->probe + l->decision_map : 0;
        }, "Every photon the run traced (its sidecar's photons.traced ledger summed; 0 without a photon map).")
        .def("save", &save, py::arg("path"),
             "Writes PATH (must end in .exr), its PNG preview and its JSON sidecar exactly as `vpm render -o PATH` "
             "does: destinations checked first, the three files replaced together or not at all.");
    m.def("_render", &render, py::arg("config"), py::arg("threads") = py::none(), py::arg("progress") = true,
          py::arg("log") = false, py::arg("stream_offset") = 0);
    m.def("read_exr", &read_exr_array, py::arg("path"),
          "Reads an EXR's RGB channels as a float32 array (height, width, 3), as vpm compare and sweeps read them.");
}

}  // namespace vpm::python
