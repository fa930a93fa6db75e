#pragma once
// A parameter sweep: the sweep file, and its expansion into a plan of runs.
//
// Sweep file (TOML; relative paths from the sweep file's folder):
//   scene = "../default_photon_map.toml"   # base scene config (required)
//   set = ["render.width=96"]              # fixed overrides for every run, as `vpm render --set`
//   repeats = 3                            # independent photon maps + camera streams per point
//   time_budgets = [2.0, 8.0]              # seconds, for the equal-time table (optional; default:
//                                          # the time_limit axis's values, else 3 from the data)
//   metric = "relmse"                      # the report's error: relmse (default), relrmse or smape
//   metric_epsilon = 0.01                  # eps of relmse and smape (analysis/metrics/error_metrics.h)
//   [reference]
//   spp = 1024                             # render it with the path tracer (cached, in up to
//                                          # 16 passes for its variance image), or
//   file = "ref.exr"                       # use this EXR (only when no axis changes the scene:
//                                          # photons.* and time_limit axes do not)
//   path_spp = [4, 16, 64]                 # the path tracer's own error-vs-time curve (optional)
//   [axes]                                 # each a list; the plan is their Cartesian product
//   estimator = ["classic", "corrected"]   # short for photons.estimator
//   k = [8, 16, 32]                        # short for photons.k
//   time_limit = [1, 4, 16]                # short for render.time_limit: equal-time runs of
//                                          # both methods (path runs keep render.time_limit)
//   "photons.count" = [10000, 100000]      # any scene key by its dotted path
//   "media.0.g" = [0.0, 0.5]
//
// Axis runs use render.integrator = "photon_map". Path tracer runs use every axis except the
// [photons] ones, with render.spp from reference.path_spp. Repeat r runs with the scene's
// render.seed and stream offset r (RunOptions::stream_offset): independent photon maps and camera
// samples. Every run's scene config is built (Scene::build) while planning, so a bad axis key or a
// value of the wrong type fails before any work, naming the sweep file, the axis and the value.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace vpm {

struct SweepAxis {
    std::string name;                  // as written in [axes]
    std::string key;                   // dotted scene path (k -> photons.k)
    std::vector<std::string> values;   // TOML text of each value ("0.5", "\"classic\"", "[1, 1, 1]")
    std::vector<std::string> labels;   // for tables: strings unquoted
    int line = 0;
    bool photon_only() const { return key.rfind("photons.", 0) == 0; }
    // A time budget: how long the runs render, not what (one reference serves every value).
    bool budget_only() const { return key == "render.time_limit"; }
};

struct SweepSpec {
    std::string file;                       // as given, for messages
    std::filesystem::path scene;            // resolved path of the base scene
    std::vector<std::string> set;
    int repeats = 1;
    std::vector<double> time_budgets;
    std::string metric = "relmse";          // parse_error_metric's names
    double metric_epsilon = 0.01;
    std::filesystem::path reference_file;   // empty: render a reference
    int reference_spp = 0;
    std::vector<int> path_spp;
    std::vector<SweepAxis> axes;
};

// Throws ConfigError "<file>:<line>: <key>: <message>".
SweepSpec load_sweep(const std::string& path);
SweepSpec parse_sweep(const std::string& text, const std::string& name, const std::filesystem::path& base_dir);

struct PlannedRun {
    size_t index = 0;                   // position in the full plan (shards take index % N == i)
    std::string method;                 // the estimator name, or "path"
    std::vector<std::string> overrides; // set + axis values + integrator/spp, for load_config
    std::vector<std::string> values;    // label per axis ("" where the axis does not apply)
    int spp = 0;
    int repeat = 0;
    uint64_t seed = 0, stream_offset = 0;
    std::string hash;                   // run_hash: the row's identity
    std::string point;                  // hash of the config without the stream: groups repeats
    std::string scene;                  // scene_hash: the reference it is compared with
};

struct SweepPlan {
    SweepSpec spec;
    std::vector<PlannedRun> runs;
    // scene hash -> overrides that render its reference (path tracer, reference spp)
    std::map<std::string, std::vector<std::string>> references;
};

// Stream offset of reference renders (far from any repeat's).
constexpr uint64_t kReferenceStream = 1000003;

// Expands and validates; `log` gets a line now and then (may be empty).
SweepPlan plan_sweep(const SweepSpec& spec, const std::function<void(const std::string&)>& log = {});

}  // namespace vpm
