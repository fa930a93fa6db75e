// vpm compare IMAGE... REFERENCE [--metric M] [--epsilon E] [--crop R] [--exclude R]... [--mask F] [--exclude-lights C]
//             [--reference-variance F | --reference-halves A B] [--json] [--repeats]
// Each IMAGE against REFERENCE (the last argument, or the mean of two halves) by a named metric
// (lib/analysis/metrics/error_metrics.h; relMSE by default), with the reference's noise floor subtracted
// when it is known (REFERENCE.variance.exr beside it, --reference-variance, or the halves), over the
// pixels a mask keeps; beside it the other metrics, the channel-wise RMSE and relative bias, and the
// luminance metrics `vpm sweep` reports. --repeats takes the images as independent repeats of one
// configuration and adds the sweep's repeat metrics and the named metric's mean and standard error.
// An image whose sidecar records more camera samples than the reference's gets a warning on stderr.
#include <cmath>
#include <cstdio>
#include <iostream>
#include <string>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "analysis/metrics/error_metrics.h"
#include "analysis/metrics/pixel_mask.h"
#include "analysis/metrics/reference_noise.h"
#include "analysis/metrics/reference_samples.h"
#include "analysis/metrics/seen_lights.h"
#include "arguments.h"
#include "command.h"
#include "render/run/image_io.h"
#include "render/run/run_config.h"
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
    CLI::App app("Compare EXR images with a reference EXR (the last argument): a named metric (relMSE by default) with the "
                 "reference's noise floor subtracted, the other metrics, relative bias; with --repeats, the sweep's bias +- "
                 "standard error over the images as repeats.",
                 "vpm compare");
    std::vector<std::string> files, excludes, halves;
    bool json = false, repeats = false;
    std::string metric_text = "relmse", crop, mask_file, variance_file, lights_config;
    double epsilon = vpm::kDefaultMetricEpsilon;
    app.add_option("images", files, "IMAGE.exr... REFERENCE.exr: the images to judge, then the reference (same size)")
        ->check(CLI::ExistingFile);
    app.add_flag("--json", json, "JSON instead of text: one object for one image, else {reference, images, repeats}");
    app.add_flag("--repeats", repeats,
                 "The images are independent repeats of one configuration: add relative bias +- standard error, "
                 "variance and MSE over them (as vpm sweep's points.csv)");
    app.add_option("--metric", metric_text,
                   "The error reported first, with the reference's noise floor subtracted: relmse (mean (I-R)^2 / (R^2 + eps), "
                   "the per-pixel relative MSE of rendering papers), relrmse (sqrt(mean (I-R)^2) / mean R) or smape "
                   "(mean |I-R| / (|I| + |R| + eps)); all on luminance (docs/metrics.md)")
        ->capture_default_str();
    app.add_option("--epsilon", epsilon, "eps of relmse and smape: keeps black pixels from dominating")
        ->capture_default_str()
        ->check(vpm::cli::finite_in(1e-12, 1e12, "a number > 0"));
    app.add_option("--crop", crop, "Compare only the pixels in X0,Y0,X1,Y1 (half-open, row 0 at the top)");
    app.add_option("--exclude", excludes, "Leave out the pixels in X0,Y0,X1,Y1 (e.g. a glint); repeatable")
        ->allow_extra_args(false);
    app.add_option("--mask", mask_file, "EXR of the images' size: compare only where it is non-zero")->check(CLI::ExistingFile);
    app.add_option("--exclude-lights", lights_config,
                   "CONFIG.toml or a run record (RUN.json): leave out the pixels where its scene shows an area light, straight or "
                   "through mirrors and glass (lib/analysis/metrics/seen_lights.h)")
        ->check(CLI::ExistingFile);
    app.add_option("--reference-variance", variance_file,
                   "Per-pixel luminance variance of the reference (default: REFERENCE.variance.exr beside it when it exists, "
                   "written by vpm render --variance)")
        ->check(CLI::ExistingFile);
    app.add_option("--reference-halves", halves,
                   "A.exr B.exr: the reference as two halves rendered on independent streams (their mean; the noise floor "
                   "from their difference); then every positional argument is an image")
        ->expected(2)
        ->allow_extra_args(false)
        ->check(CLI::ExistingFile);
    if (!vpm::cli::parse_arguments(app, argc, argv)) return 0;
    vpm::MetricOptions metric;
    try {
        metric.metric = vpm::parse_error_metric(metric_text);
    } catch (const vpm::Error& e) {
        throw vpm::cli::UsageError(std::string("--metric: ") + e.what());
    }
    metric.epsilon = epsilon;
    if (!halves.empty() && !variance_file.empty())
        throw vpm::cli::UsageError("--reference-halves and --reference-variance: give one (the halves carry their own noise)");
    if (files.size() < (halves.empty() ? 2u : 1u))
        throw vpm::cli::UsageError(halves.empty() ? "images: give at least one image and then the reference"
                                                  : "images: give at least one image (the reference is --reference-halves)");
    std::string reference;
    if (halves.empty()) {
        reference = files.back();
        files.pop_back();
    }
    if (repeats && files.size() < 2) throw vpm::cli::UsageError("--repeats: needs two or more images");
    const vpm::NoisyReference noisy = halves.empty() ? vpm::load_reference(reference, variance_file)
                                                     : vpm::load_reference_halves(halves[0], halves[1]);
    if (!halves.empty()) reference = noisy.name;
    const vpm::Image& r = noisy.image;
    check_finite(reference, r);
    vpm::PixelMask mask(r.width, r.height);
    if (!crop.empty()) mask.crop(vpm::parse_pixel_rect(crop, "--crop"));
    for (const std::string& e : excludes) mask.exclude(vpm::parse_pixel_rect(e, "--exclude"));
    if (!mask_file.empty()) mask.intersect(vpm::read_exr(mask_file), mask_file);
    if (!lights_config.empty()) vpm::exclude_seen_lights(mask, *vpm::RunConfig::load(lights_config).scene, lights_config);
    metric.mask = &mask;
    const vpm::Image* variance = noisy.variance ? &*noisy.variance : nullptr;
    std::vector<vpm::Image> images;
    for (const std::string& f : files) {
        images.push_back(vpm::read_exr(f));
        check_finite(f, images.back());
        if (images.back().width != r.width || images.back().height != r.height)
            throw vpm::Error(f + ": " + std::to_string(images.back().width) + "x" + std::to_string(images.back().height) +
                             ", but the reference " + reference + " is " + std::to_string(r.width) + "x" +
                             std::to_string(r.height));
    }
    // The reference's camera samples where its sidecar says (halves: both halves'), 0 when unknown.
    uint64_t reference_samples = 0;
    if (halves.empty()) {
        reference_samples = vpm::recorded_samples(reference).value_or(0);
    } else {
        const uint64_t a = vpm::recorded_samples(halves[0]).value_or(0), b = vpm::recorded_samples(halves[1]).value_or(0);
        reference_samples = a > 0 && b > 0 ? a + b : 0;
    }
    const std::string formula = vpm::metric_formula(metric.metric, metric.epsilon);
    const std::string noise_text = noisy.variance ? "reference noise from " + noisy.noise_source + ", subtracted"
                                                  : "reference noise unknown (no " + vpm::variance_path_for(reference).string() +
                                                        "): not subtracted";
    if (!json) std::printf("metric: %s; %s; %s\n", formula.c_str(), mask.describe().c_str(), noise_text.c_str());
    // The other two metrics beside the chosen one, on the same pixels with the same floor.
    auto other_metrics = [&](const vpm::Image& im) {
        std::vector<vpm::MetricValue> v;
        for (vpm::ErrorMetric m : {vpm::ErrorMetric::rel_mse, vpm::ErrorMetric::rel_rmse, vpm::ErrorMetric::smape}) {
            vpm::MetricOptions o = metric;
            o.metric = m;
            v.push_back(vpm::measure_error(im, r, o, variance));
        }
        return v;
    };
    auto metric_json = [&](const vpm::MetricValue& v) {
        return nlohmann::json{{"value", number(v.value)}, {"raw", number(v.raw)}, {"noise_floor", number(v.floor)}};
    };
    std::vector<vpm::MetricValue> chosen;
    nlohmann::json out_images = nlohmann::json::array();
    for (size_t i = 0; i < files.size(); ++i) {
        const vpm::ImageError e = vpm::compare_images(images[i], r);
        const vpm::RunError y = vpm::run_error(images[i], r);
        const std::optional<uint64_t> samples = vpm::recorded_samples(files[i]);
        if (samples && reference_samples)
            if (const std::string w = vpm::more_samples_warning(files[i], *samples, reference, reference_samples); !w.empty())
                std::cerr << w << "\n";
        const vpm::MetricValue m = vpm::measure_error(images[i], r, metric, variance);
        chosen.push_back(m);
        const std::vector<vpm::MetricValue> all = other_metrics(images[i]);
        nlohmann::json j = {{"image", files[i]}, {"reference", reference},
                            {"metric", vpm::metric_name(m.metric)}, {"metric_formula", formula}, {"epsilon", m.epsilon},
                            {"error", number(m.value)}, {"error_raw", number(m.raw)}, {"noise_floor", number(m.floor)},
                            {"noise_source", noisy.noise_source}, {"pixels", m.pixels}, {"masked_out", m.masked_out},
                            {"mask", mask.describe()},
                            {"relmse", metric_json(all[0])}, {"relrmse", metric_json(all[1])}, {"smape", metric_json(all[2])},
                            {"rmse", e.rmse},
                            {"relative_rmse", e.relative_rmse}, {"relative_bias", e.relative_bias}, {"mean", e.mean},
                            {"reference_mean", e.reference_mean}, {"nonfinite", e.nonfinite},
                            {"luminance_rel_rmse", y.rel_rmse}, {"luminance_rel_bias", y.rel_mean_error}};
        if (samples) j["samples"] = *samples;
        if (reference_samples) j["reference_samples"] = reference_samples;
        out_images.push_back(j);
        if (!json)
            std::printf("%s vs %s: %s; relMSE %.4g, relRMSE %.4g, SMAPE %.4g; relative bias %+.4f (mean %.6g, reference %.6g); "
                        "channel-wise rmse %.6g, relative rmse %.4f; luminance over all pixels, noise included (as vpm sweep's "
                        "runs.csv): relative rmse %.4f, relative bias %+.4f\n",
                        files[i].c_str(), reference.c_str(), vpm::describe(m).c_str(), all[0].value, all[1].value, all[2].value,
                        e.relative_bias, e.mean, e.reference_mean, e.rmse, e.relative_rmse, y.rel_rmse, y.rel_mean_error);
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
        // The named metric over the repeats: its mean and the standard error of that mean.
        double mean = 0, var = 0;
        for (const auto& m : chosen) mean += m.value / double(chosen.size());
        for (const auto& m : chosen) var += (m.value - mean) * (m.value - mean) / double(chosen.size() - 1);
        const double se = std::sqrt(var / double(chosen.size()));
        out_repeats["metric"] = vpm::metric_name(metric.metric);
        out_repeats["error"] = number(mean);
        out_repeats["error_se"] = number(se);
        out_repeats["noise_floor"] = number(chosen[0].floor);
        if (!json)
            std::printf("%zu repeats: %s %.4g +- %.2g (mean +- standard error over the repeats)\n", e.repeats,
                        vpm::metric_name(metric.metric).c_str(), mean, se);
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

VPM_REGISTER_COMMAND({"compare", "relMSE / relRMSE / SMAPE / bias of EXR images against a reference EXR, its noise subtracted", run_compare});
