// vpm.study and vpm.sweep: the estimator study (lib/analysis/study/study.h) and parameter sweeps
// (lib/analysis/sweep/sweep.h), writing the tool's files; vpm/__init__.py turns their tables into rows.
#include <filesystem>
#include <iostream>
#include <optional>

#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <nlohmann/json.hpp>

#include "analysis/scene_info.h"
#include "analysis/study/study.h"
#include "analysis/sweep/sweep.h"
#include "analysis/sweep/sweep_plan.h"
#include "bindings.h"
#include "native_call.h"
#include "render/run/image_io.h"
#include "render/run/run_config.h"
#include "render/run/staged_file.h"

namespace py = pybind11;
namespace fs = std::filesystem;

namespace vpm::python {

namespace {

std::function<void(const std::string&)> stderr_log(bool enabled) {
    if (!enabled) return {};
    return [](const std::string& s) { std::cerr << s << std::endl; };
}

// Returns (study.csv text, study.md text, notes); writes study.csv, study.md and study.json into
// `out` unless it is None, as `vpm study --out OUT --no-plots` does.
py::tuple study(std::optional<fs::path> out, std::vector<int> dims, std::vector<size_t> ks, size_t trials, size_t n,
                uint64_t seed, std::optional<std::vector<std::string>> scenarios, size_t photon_map_size, int threads,
                bool log) {
    StudyOptions opt;
    opt.dims = std::move(dims);
    opt.ks = std::move(ks);
    opt.trials = trials;
    opt.n = n;
    opt.seed = seed;
    opt.photon_map_size = photon_map_size;
    if (scenarios) {
        opt.scenarios.clear();
        for (const auto& s : *scenarios) opt.scenarios.push_back(parse_scenario(s));
    }
    std::string csv, markdown;
    std::vector<std::string> notes;
    call_native(
        [&](const std::atomic<bool>& interrupted) {
            if (out) {   // before the work: an unwritable folder fails now
                prepare_output_folder(*out);
                for (const char* name : {"study.csv", "study.md", "study.json"}) check_output_file(*out / name);
            }
            const StudyResult res = run_estimator_study(opt, stderr_log(log));
            if (interrupted) return;   // cancelled trials: nothing is written
            csv = study_csv(res);
            markdown = study_markdown(res);
            notes = res.notes;
            if (out) {
                write_text_atomic(*out / "study.csv", csv);
                write_text_atomic(*out / "study.md", markdown);
                write_text_atomic(*out / "study.json", study_sidecar_json(res));
            }
        },
        threads);
    return py::make_tuple(csv, markdown, notes);
}

// Runs the sweep file into `out` as `vpm sweep FILE --out OUT --no-plots` does; returns the counts.
py::dict sweep(const std::string& file, const fs::path& out, int jobs, int threads, size_t max_runs, int shard,
               int shards, bool references_only, bool progress, bool log) {
    SweepOutcome res;
    call_native(
        [&](const std::atomic<bool>& interrupted) {
            SweepOptions opt;
            opt.out = out;
            opt.jobs = jobs;
            opt.max_runs = max_runs;
            opt.shard = shard;
            opt.shards = shards;
            opt.references_only = references_only;
            opt.progress = progress;
            opt.log = stderr_log(log);
            opt.command_line = {"vpm.sweep", file};
            opt.cancelled = [&interrupted] { return interrupted.load(); };
            res = run_sweep(plan_sweep(load_sweep(file), opt.log), opt);
        },
        threads);
    py::dict d;
    d["planned"] = res.planned;
    d["in_shard"] = res.in_shard;
    d["skipped"] = res.skipped;
    d["ran"] = res.ran;
    d["remaining"] = res.remaining;
    d["seconds"] = res.seconds;
    d["csv"] = res.csv;
    return d;
}

// vpm info TARGET --json: a VDB file's grids or a config's scene, as JSON text.
std::string info(const std::string& target, const std::vector<std::string>& sets, bool vdb) {
    std::string text;
    call_native([&](const std::atomic<bool>&) {
        text = (vdb ? vdb_info(target) : scene_info(RunConfig::load(target, sets))).dump();
    });
    return text;
}

}  // namespace

void bind_analysis(py::module_& m) {
    m.def("_info", &info, py::arg("target"), py::arg("sets"), py::arg("vdb"));
    m.def("_study", &study, py::arg("out"), py::arg("dims"), py::arg("ks"), py::arg("trials"), py::arg("n"),
          py::arg("seed"), py::arg("scenarios"), py::arg("photon_map_size"), py::arg("threads"), py::arg("log"));
    m.def("_sweep", &sweep, py::arg("file"), py::arg("out"), py::arg("jobs"), py::arg("threads"), py::arg("max_runs"),
          py::arg("shard"), py::arg("shards"), py::arg("references_only"), py::arg("progress"), py::arg("log"));
}

}  // namespace vpm::python
