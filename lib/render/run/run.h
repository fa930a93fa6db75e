#pragma once
// One complete run of a config: the chosen integrator's passes (prepare), the camera pass, its
// statistics (collect), typed in RunStats and serialised once into a RunRecord with the build
// log and the fully resolved config. Shared by `vpm render`, sweeps, the stress matrix and
// benchmarks so that they all measure the same thing.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <ostream>

#include "render/run/image.h"
#include "render/run/render_loop.h"
#include "render/run/run_config.h"
#include "render/run/run_record.h"
#include "render/run/run_stats.h"

namespace vpm {

// A group of `passes` passes rendered together in one pass over the image (render_passes; one pass for an
// integrator with per-pass state such as the photon map's photon pass).
struct PassGroupStats {
    int64_t passes_done = 0;   // passes of the run so far, this group's included
    int64_t passes = 1;        // passes in this group
    int spp = 0;               // samples per pixel of each pass
    double seconds = 0.0;      // this group, all phases
    double elapsed = 0.0;      // since the run started, at its end
    double image_mean = 0.0;   // mean of its passes' image means
};

struct RunOptions {
    bool progress = true;            // progress bars on stderr (only drawn on a terminal)
    std::ostream* log = nullptr;     // one line per phase and subsystem; null: silent
    uint64_t stream_offset = 0;      // independent repeats with the same seed
    // Called after every group with the mean image so far and the group's statistics (e.g. to
    // write the error against a reference as the passes go); may be empty.
    std::function<void(const Image& mean_so_far, const PassGroupStats& group)> on_pass;
    // Called after every group with its statistics only (cheap: no mean image); may be empty.
    std::function<void(const PassGroupStats& group)> on_pass_group;
    // Keep each pixel's squared luminance per pass, so that RunResult::variance holds the variance of
    // the final image's luminance (the spread of the independent passes: each pass has its own
    // streams and, for the photon map, its own photon map). Needs two or more passes.
    bool pass_variance = false;
    // Polled after every group of passes; true ends the run there (the Python module's Ctrl-C: the
    // caller discards that result). May be empty.
    std::function<bool()> cancelled;
};

struct RunResult {
    Image image;
    RunStats stats;
    RunRecord record;   // the stats, written once, with the config and environment
    // With RunOptions::pass_variance and two or more passes: per pixel, the variance of the image's
    // luminance as an estimate, sum_j (Y_j - Y)^2 / (N (N - 1)) over the N passes' luminances Y_j
    // (grey: the same in all three channels). Empty otherwise.
    Image variance;
};

RunResult run(const RunConfig& config, const RunOptions& options);

}  // namespace vpm
