#pragma once
// One complete run of a config: the chosen integrator's passes (prepare), the camera pass, its
// statistics (collect), typed in RunStats and serialised once into a RunRecord with the build
// log and the fully resolved config. Shared by `vpm render`, sweeps, the stress matrix and
// benchmarks so that they all measure the same thing.
#include <filesystem>
#include <functional>
#include <ostream>

#include "render/image.h"
#include "render/render_loop.h"
#include "render/run_config.h"
#include "render/run_record.h"
#include "render/run_stats.h"

namespace vpm {

struct RunOptions {
    bool progress = true;            // progress bars on stderr (only drawn on a terminal)
    std::ostream* log = nullptr;     // one line per phase and subsystem; null: silent
    uint64_t stream_offset = 0;      // independent repeats with the same seed
    // Called after every pass with the mean image so far and that pass's statistics (e.g. to
    // write the error against a reference as the passes go); may be empty.
    std::function<void(const Image& mean_so_far, const PassStats& pass)> on_pass;
    // Polled after every pass; true ends the run there (the Python module's Ctrl-C: the caller
    // discards that result). May be empty.
    std::function<bool()> cancelled;
};

struct RunResult {
    Image image;
    RunStats stats;
    RunRecord record;   // the stats, written once, with the config and environment
};

RunResult run(const RunConfig& config, const RunOptions& options);

}  // namespace vpm
