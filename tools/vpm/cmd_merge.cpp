// vpm merge A.exr B.exr ... -o OUT.exr: pass sets rendered apart, combined exactly.
#include <iostream>

#include <CLI/CLI.hpp>

#include "analysis/sweep/merge_runs.h"
#include "arguments.h"
#include "command.h"
#include "render/run/run.h"
#include "render/run/run_outputs.h"

namespace {

int run_merge(int argc, char** argv) {
    CLI::App app("Combine pass sets rendered apart (render.first_pass, e.g. one per machine or Slurm array task) "
                 "into the image one machine would have rendered: the mean weighted by each input's pass count. "
                 "Refuses inputs of different scenes or settings, different samples per pass, or overlapping passes.",
                 "vpm merge");
    std::vector<std::string> inputs;
    std::string output;
    bool quiet = false;
    app.add_option("inputs", inputs, "EXR images, each with its JSON sidecar")->required()->check(CLI::ExistingFile);
    app.add_option("-o,--output", output, "Merged EXR (+ .png preview, .json sidecar)")->required();
    app.add_flag("-q,--quiet", quiet, "No log on stderr");
    if (!vpm::cli::parse_arguments(app, argc, argv)) return 0;
    vpm::check_run_outputs(output);   // before reading the inputs

    std::vector<std::filesystem::path> paths(inputs.begin(), inputs.end());
    vpm::MergedRun merged = vpm::merge_runs(paths);
    vpm::RunResult result;
    result.image = std::move(merged.image);
    result.record = std::move(merged.record);
    vpm::write_run_outputs(output, result, merged.exposure);
    if (!quiet) std::cerr << "merge: " << inputs.size() << " images, " << merged.passes << " passes -> " << output << "\n";
    // As vpm render does: NaN or Inf in an input survives the weighted mean, so say so.
    if (const size_t bad = vpm::count_nonfinite_pixels(result.image))
        std::cerr << "vpm merge: warning: " << bad << " of " << size_t(result.image.width) * size_t(result.image.height)
                  << " pixels are NaN or Inf (render.nonfinite_pixels in " << vpm::sidecar_path_for(output).string() << ")\n";
    if (const size_t negative = vpm::count_negative_pixels(result.image))
        std::cerr << "vpm merge: warning: " << negative << " of " << size_t(result.image.width) * size_t(result.image.height)
                  << " pixels are negative, which no radiance is (render.negative_pixels in "
                  << vpm::sidecar_path_for(output).string() << ")\n";
    return 0;
}

}  // namespace

VPM_REGISTER_COMMAND({"merge", "combine pass sets rendered apart into one image (exact, by pass counts)", run_merge});
