// vpm compare IMAGE.exr REFERENCE.exr [--json]
// Prints RMSE, relative RMSE (RMSE / mean of the reference) and relative bias of IMAGE against
// REFERENCE over all pixels and channels (lib/analysis/error_metrics.h).
#include <cstdio>
#include <iostream>

#include <CLI/CLI.hpp>

#include "analysis/error_metrics.h"
#include "command.h"
#include "render/image_io.h"

namespace {

int run_compare(int argc, char** argv) {
    CLI::App app("Compare an EXR image with a reference EXR: RMSE, relative RMSE, relative bias.", "vpm compare");
    std::string image, reference;
    bool json = false;
    app.add_option("image", image, "Image to judge (EXR)")->required()->check(CLI::ExistingFile);
    app.add_option("reference", reference, "Reference image (EXR), same size")->required()->check(CLI::ExistingFile);
    app.add_flag("--json", json, "One JSON object instead of text");
    CLI11_PARSE(app, argc, argv);
    const vpm::Image a = vpm::read_exr(image), r = vpm::read_exr(reference);
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
                    e.reference_mean, y.rel_rmse, y.rel_mean_error, e.nonfinite ? ", non-finite values left out" : "");
    return 0;
}

}  // namespace

VPM_REGISTER_COMMAND({"compare", "RMSE / relative RMSE / bias of an EXR against a reference EXR", run_compare});
