#include "render/run/run_outputs.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/progress.h"
#include "render/run/image_io.h"
#include "render/run/run_record.h"
#include "render/run/staged_file.h"

namespace fs = std::filesystem;

namespace vpm {

namespace {

fs::path folder_of(const fs::path& output) {
    return output.has_parent_path() ? output.parent_path() : fs::path(".");
}

}  // namespace

void check_run_outputs(const fs::path& output, const std::vector<fs::path>& extra) {
    std::string ext = output.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    if (ext != ".exr")
        throw FileError(output.string() + ": the output must be an OpenEXR file name ending in .exr (the PNG "
                                          "preview and the JSON sidecar are written beside it, as " +
                        preview_path_for(output).filename().string() + " and " +
                        sidecar_path_for(output).filename().string() + ")");
    // A link named as the image would take the image elsewhere and leave the preview and the
    // sidecar beside the link (their names come from the path as given): the set would part.
    if (fs::is_symlink(output)) {
        check_output_file(output);   // a link to a device or folder is named as such first
        const fs::path target = resolve_output_target(output);
        throw FileError(output.string() + ": is a symbolic link to " + target.string() + "; the image would be written " +
                        "there and its preview and sidecar beside the link (" + preview_path_for(output).string() +
                        ", " + sidecar_path_for(output).string() + "), apart from it. Give " + target.string() +
                        " itself as the output (all three are written beside it), or a path that is not a link");
    }
    // The folder first: a missing one is created here, before the work, not after it.
    prepare_output_folder(folder_of(output));
    std::vector<fs::path> all = {output, preview_path_for(output), sidecar_path_for(output)};
    all.insert(all.end(), extra.begin(), extra.end());
    for (const fs::path& p : all) {
        check_output_file(p);
        prepare_output_folder(folder_of(resolve_output_target(p)));   // a symlink may lead elsewhere
    }
}

size_t count_nonfinite_pixels(const Image& image) {
    size_t n = 0;
    for (size_t i = 0; i + 2 < image.rgb.size(); i += 3)
        n += !(std::isfinite(image.rgb[i]) && std::isfinite(image.rgb[i + 1]) && std::isfinite(image.rgb[i + 2]));
    return n;
}

size_t count_negative_pixels(const Image& image) {
    size_t n = 0;
    for (size_t i = 0; i + 2 < image.rgb.size(); i += 3) n += image.rgb[i] < 0.0f || image.rgb[i + 1] < 0.0f || image.rgb[i + 2] < 0.0f;
    return n;
}

void write_run_outputs(const fs::path& output, RunResult& result, double exposure,
                       const std::vector<std::pair<fs::path, std::string>>& extra_text, std::vector<StagedFile> staged) {
    std::vector<fs::path> extra;
    for (const auto& [path, text] : extra_text) extra.push_back(path);
    for (const StagedFile& f : staged) extra.push_back(f.path());
    check_run_outputs(output, extra);
    const Timer timer;
    // The final image, not the samples: finite samples can still sum to an Inf pixel.
    result.record.set("render.nonfinite_pixels", uint64_t(count_nonfinite_pixels(result.image)));
    result.record.set("render.negative_pixels", uint64_t(count_negative_pixels(result.image)));
    std::vector<StagedFile> files;
    files.push_back(stage_exr(output, result.image));
    files.push_back(stage_png_preview(preview_path_for(output), result.image, exposure));
    result.record.phase("write", timer.seconds());
    result.record.set("output.exr", output.string());
    result.record.set("output.png", preview_path_for(output).string());
    result.record.set("peak_rss_bytes", peak_rss_bytes());
    files.push_back(stage_text(sidecar_path_for(output), result.record.dump(2) + "\n"));
    for (const auto& [path, text] : extra_text) files.push_back(stage_text(path, text));
    for (StagedFile& f : staged) files.push_back(std::move(f));
    commit_together(files);
}

}  // namespace vpm
