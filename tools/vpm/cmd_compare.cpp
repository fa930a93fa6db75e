// vpm compare IMAGE... REFERENCE [--json] [--repeats]
// Each IMAGE against REFERENCE (the last argument): channel-wise RMSE, relative RMSE and relative
// bias, and the luminance metrics `vpm sweep` reports (lib/analysis/error_metrics.h). --repeats
// takes the images as independent repeats of one configuration and adds the sweep's repeat
// metrics (relative bias with its standard error, variance, MSE = bias^2 + variance). An image
// whose sidecar records more camera samples than the reference's gets a warning on stderr.
#include <cstdio>
#include <iostream>
#include <string>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "analysis/error_metrics.h"
#include "analysis/reference_samples.h"
#include "arguments.h"
#include "command.h"
#include "render/run/image_io.h"
#include "render/run/run_outputs.h"

namespace {

// NaN/Inf pixels would be left out of the sums, and an image that is half Inf could score
// "rmse 0": refuse to measure it instead, naming the file and how many pixels are bad.
void check_finite(const std::string& name, const vpm::Image& img) {
    if (const size_t bad = vpm::count_nonfinite_pixels(img))
        throw vpm::Error(name + ": " + std::to_string(bad) + " of " + std::to_string(size_t(img.width) * size_t(img.height)) +
                         " pixels are NaN or Inf; the error against the reference is undefined");
}

// A number for JSON: NaN (one repeat's standard error) as null.
nlohmann::json number(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

int run_compare(int argc, char** argv) {
    CLI::App app("Compare EXR images with a reference EXR (the last argument): RMSE, relative RMSE, relative bias; "
                 "with --repeats, the sweep's bias +- standard error over the images as repeats.",
                 "vpm compare");
    std::vector<std::string> files;
    bool json = false, repeats = false;
    app.add_option("images", files, "IMAGE.exr... REFERENCE.exr: the images to judge, then the reference (same size)")
        ->required()
        ->check(CLI::ExistingFile);
    app.add_flag("--json", json, "JSON instead of text: one object for one image, else {reference, images, repeats}");
    app.add_flag("--repeats", repeats,
                 "The images are independent repeats of one configuration: add relative bias +- standard error, "
                 "variance and MSE over them (as vpm sweep's points.csv)");
    if (!vpm::cli::parse_arguments(app, argc, argv)) return 0;
    if (files.size() < 2) throw vpm::cli::UsageError("images: give at least one image and then the reference");
    const std::string reference = files.back();
    files.pop_back();
    if (repeats && files.size() < 2) throw vpm::cli::UsageError("--repeats: needs two or more images");
    const vpm::Image r = vpm::read_exr(reference);
    check_finite(reference, r);
    std::vector<vpm::Image> images;
    for (const std::string& f : files) {
        images.push_back(vpm::read_exr(f));
        check_finite(f, images.back());
        if (images.back().width != r.width || images.back().height != r.height)
            throw vpm::Error(f + ": " + std::to_string(images.back().width) + "x" + std::to_string(images.back().height) +
                             ", but the reference " + reference + " is " + std::to_string(r.width) + "x" +
                             std::to_string(r.height));
    }
    const std::optional<uint64_t> reference_samples = vpm::recorded_samples(reference);
    nlohmann::json out_images = nlohmann::json::array();
    for (size_t i = 0; i < files.size(); ++i) {
        const vpm::ImageError e = vpm::compare_images(images[i], r);
        const vpm::RunError y = vpm::run_error(images[i], r);
        const std::optional<uint64_t> samples = vpm::recorded_samples(files[i]);
        if (samples && reference_samples)
            if (const std::string w = vpm::more_samples_warning(files[i], *samples, reference, *reference_samples); !w.empty())
                std::cerr << w << "\n";
        nlohmann::json j = {{"image", files[i]}, {"reference", reference}, {"rmse", e.rmse},
                            {"relative_rmse", e.relative_rmse}, {"relative_bias", e.relative_bias}, {"mean", e.mean},
                            {"reference_mean", e.reference_mean}, {"nonfinite", e.nonfinite},
                            {"luminance_rel_rmse", y.rel_rmse}, {"luminance_rel_bias", y.rel_mean_error}};
        if (samples) j["samples"] = *samples;
        if (reference_samples) j["reference_samples"] = *reference_samples;
        out_images.push_back(j);
        if (!json)
            std::printf("%s vs %s: rmse %.6g, relative rmse %.4f, relative bias %+.4f (mean %.6g, reference %.6g); "
                        "luminance (as vpm sweep): relative rmse %.4f, relative bias %+.4f\n",
                        files[i].c_str(), reference.c_str(), e.rmse, e.relative_rmse, e.relative_bias, e.mean,
                        e.reference_mean, y.rel_rmse, y.rel_mean_error);
    }
    nlohmann::json out_repeats;
    if (repeats) {
        std::vector<const vpm::Image*> ptrs;
        for (const auto& im : images) ptrs.push_back(&im);
        const vpm::RepeatError e = vpm::repeat_error(ptrs, r);
        out_repeats = {{"repeats", e.repeats},          {"rel_rmse", number(e.rel_rmse)},
                       {"rel_mse", number(e.rel_mse)},   {"rel_bias", number(e.rel_bias)},
                       {"rel_bias_se", number(e.rel_bias_se)}, {"rel_bias2", number(e.rel_bias2)},
                       {"rel_variance", number(e.rel_variance)}, {"rel_std", number(e.rel_std)}};
        if (!json)
            std::printf("%zu repeats (luminance, as vpm sweep's points.csv): relative rmse %.4f, relative bias %+.4f +- %.2g "
                        "(standard error), rel std %.4f, rel bias^2 %.4g, rel variance %.4g\n",
                        e.repeats, e.rel_rmse, e.rel_bias, e.rel_bias_se, e.rel_std, e.rel_bias2, e.rel_variance);
    }
    if (json) {
        if (files.size() == 1 && !repeats) {
            std::printf("%s\n", out_images[0].dump().c_str());
        } else {
            nlohmann::json all = {{"reference", reference}, {"images", out_images}};
            if (repeats) all["repeats"] = out_repeats;
            std::printf("%s\n", all.dump().c_str());
        }
    }
    return 0;
}

}  // namespace

VPM_REGISTER_COMMAND({"compare", "RMSE / relative RMSE / bias of EXR images against a reference EXR", run_compare});
