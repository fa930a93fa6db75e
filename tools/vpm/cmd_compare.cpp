// vpm compare IMAGE.exr REFERENCE.exr [--json]
// Prints RMSE, relative RMSE (RMSE / mean of the reference) and relative bias of IMAGE against
// REFERENCE over all pixels and channels (lib/analysis/error_metrics.h).
#include <cstdio>
#include <utility>
#include <iostream>

#include <CLI/CLI.hpp>

#include "analysis/error_metrics.h"
#include "arguments.h"
#include "command.h"
#include "render/run/image_io.h"
#include "render/run/run_outputs.h"

namespace {

int run_compare(int argc, char** argv) {
    CLI::App app("Compare an EXR image with a reference EXR: RMSE, relative RMSE, relative bias.", "vpm compare");
    std::string image, reference;
    bool json = false;
    app.add_option("image", image, "Image to judge (EXR)")->required()->check(CLI::ExistingFile);
    app.add_option("reference", reference, "Reference image (EXR), same size")->required()->check(CLI::ExistingFile);
    app.add_flag("--json", json, "One JSON object instead of text");
    if (!vpm::cli::parse_arguments(app, argc, argv)) return 0;
    const vpm::Image a = vpm::read_exr(image), r = vpm::read_exr(reference);
    // NaN/Inf pixels would be left out of the sums, and an image that is half Inf could score
    // "rmse 0": refuse to measure it instead, naming the file and how many pixels are bad.
    for (const auto& [name, img] : {std::pair<const std::string&, const vpm::Image&>{image, a}, {reference, r}})
        if (const size_t bad = vpm::count_nonfinite_pixels(img))
            throw vpm::Error(name + ": " + std::to_string(bad) + " of " + std::to_string(size_t(img.width) * size_t(img.height)) +
                             " pixels are NaN or Inf; the error against the reference is undefined");
    const vpm::ImageError e = vpm::compare_images(a, r);
    const vpm::RunError y = vpm::run_error(a, r);
    if (json)
        std::printf("{\"image\": \"%s\", \"reference\": \"%s\", \"rmse\": %.6g, \"relative_rmse\": %.6g, "
                    "\"relative_bias\": %.6g, \"mean\": %.6g, \"reference_mean\": %.6g, \"nonfinite\": %zu, "
                    "\"luminance_rel_rmse\": %.6g, \"luminance_rel_bias\": %.6g}\n",
                    image.c_str(), reference.c_str(), e.rmse, e.relative_rmse, e.relative_bias, e.mean,
                    e.reference_mean, e.nonfinite, y.rel_rmse, y.rel_mean_error);
    else
        std::printf("%s vs %s: rmse %.6g, relative rmse %.4f, relative bias %+.4f (mean %.6g, reference %.6g); "
                    "luminance (as vpm sweep): relative rmse %.4f, relative bias %+.4f%s\n",
                    image.c_str(), reference.c_str(), e.rmse, e.relative_rmse, e.relative_bias, e.mean,
                    e.reference_mean, y.rel_rmse, y.rel_mean_error, "");
    return 0;
}

}  // namespace

VPM_REGISTER_COMMAND({"compare", "RMSE / relative RMSE / bias of an EXR against a reference EXR", run_compare});
