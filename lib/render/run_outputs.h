#pragma once
// The three files of one run: OUT (EXR), its PNG preview and its JSON sidecar.
#include <filesystem>

#include "render/run.h"

namespace vpm {

// Writes OUT (EXR), its PNG preview and its JSON sidecar, each atomically. Creates OUT's folder.
void write_run_outputs(const std::filesystem::path& output, RunResult& result, double exposure);

}  // namespace vpm
