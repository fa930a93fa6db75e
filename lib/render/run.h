#pragma once
// One complete run of a scene: the passes its integrator needs (photon pass and photon map
// only for the photon-map integrator), the render, and a RunRecord with every phase's time,
// peak memory, the build log and the fully resolved config. Shared by `vpm render`, sweeps
// and benchmarks so that they all measure the same thing.
#include <filesystem>
#include <ostream>

#include "render/image.h"
#include "render/render_loop.h"
#include "render/run_record.h"
#include "scene/scene.h"

namespace vpm {

struct RunOptions {
    bool progress = true;            // progress bars on stderr (only drawn on a terminal)
    std::ostream* log = nullptr;     // one line per phase and subsystem; null: silent
    uint64_t stream_offset = 0;      // independent repeats with the same seed
};

struct RunResult {
    Image image;
    RenderStats stats;
    RunRecord record;
};

RunResult run_scene(const Scene& scene, const RunOptions& options);

}  // namespace vpm
