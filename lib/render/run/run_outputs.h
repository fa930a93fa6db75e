#pragma once
// The three files of one run: OUT (EXR), its PNG preview OUT-stem.png and its JSON sidecar
// OUT-stem.json. Guarantees (docs/rendering.md, "Output files"): OUT must end in .exr; each file is written
// to a temporary and renamed, the three renames under one advisory lock on the folder, so a
// failed or interrupted run leaves the old files as they were and concurrent runs to the same
// OUT leave a set that comes from one run; symlinks are written through; special files are refused.
#include <cstddef>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "render/run/image.h"
#include "render/run/run.h"
#include "render/run/staged_file.h"

namespace vpm {

// Before any work: checks that OUT ends in .exr, that none of the three files is a folder,
// device, FIFO or socket, and creates OUT's folder and proves it writable. Throws FileError.
// `extra` are further files of the run (e.g. OUT.passes.csv), checked the same way.
void check_run_outputs(const std::filesystem::path& output, const std::vector<std::filesystem::path>& extra = {});

// Pixels with a NaN or Inf in any channel.
size_t count_nonfinite_pixels(const Image& image);

// Pixels with a negative channel (non-physical: no radiance is negative).
size_t count_negative_pixels(const Image& image);

// Records render.nonfinite_pixels, render.negative_pixels and the write phase, then writes OUT, its PNG preview, its
// JSON sidecar and the `extra_text` files (path, contents) as one set (see above). Creates OUT's
// folder. Throws FileError.
// `staged` are further files already written to their temporaries (e.g. a table streamed during
// the run); they are committed with the others.
void write_run_outputs(const std::filesystem::path& output, RunResult& result, double exposure,
                       const std::vector<std::pair<std::filesystem::path, std::string>>& extra_text = {},
                       std::vector<StagedFile> staged = {});

}  // namespace vpm
