#include "render/run_outputs.h"

#include <system_error>

#include "core/error.h"
#include "core/progress.h"
#include "render/image_io.h"
#include "render/run_record.h"

namespace vpm {

void write_run_outputs(const std::filesystem::path& output, RunResult& result, double exposure) {
    const auto folder = output.has_parent_path() ? output.parent_path() : std::filesystem::path(".");
    std::error_code ec;
    std::filesystem::create_directories(folder, ec);
    if (ec) throw FileError(folder.string() + ": cannot create output folder: " + ec.message());
    const Timer timer;
    write_exr(output, result.image);
    write_png_preview(preview_path_for(output), result.image, exposure);
    result.record.phase("write", timer.seconds());
    result.record.set("output.exr", output.string());
    result.record.set("output.png", preview_path_for(output).string());
    result.record.write(sidecar_path_for(output));
}

}  // namespace vpm
