// vpm.compare: images against a reference with the metrics `vpm sweep` and `vpm compare` report
// (lib/analysis/metrics/error_metrics.h), computed by the same code; vpm/__init__.py turns files and render
// results into arrays and adds the samples check.
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "analysis/metrics/error_metrics.h"
#include "analysis/metrics/pixel_mask.h"
#include "analysis/metrics/reference_noise.h"
#include "analysis/metrics/reference_samples.h"
#include "analysis/metrics/seen_lights.h"
#include "render/run/run_outputs.h"
#include "bindings.h"
#include "config.h"
#include "native_call.h"
#include "core/error.h"

namespace py = pybind11;

namespace vpm::python {

namespace {

using DoubleArray = py::array_t<double, py::array::c_style | py::array::forcecast>;

// An (H, W, 3) array of numbers as an Image (float32, copied). Read as float64 first, so that a
// value beyond float32's range is an error naming it, not an infinity. finite_only: NaN and Inf
// pixels are refused as `vpm compare` refuses them (the error against a reference is undefined).
Image to_image(const py::handle& h, const std::string& name, bool finite_only = true) {
    DoubleArray a;
    try {
        a = DoubleArray::ensure(h);
    } catch (const py::error_already_set&) {
        a = DoubleArray();
    }
    if (!a) throw Error(name + ": expected an array of numbers of shape (height, width, 3), got a " +
                        std::string(py::str(py::type::handle_of(h).attr("__name__"))));
    if (a.ndim() != 3 || a.shape(2) != 3)
        throw Error(name + ": expected an array of shape (height, width, 3), got " + std::to_string(a.ndim()) +
                    " dimensions" + (a.ndim() == 3 ? " with " + std::to_string(a.shape(2)) + " channels" : std::string()));
    if (a.shape(0) < 1 || a.shape(1) < 1) throw Error(name + ": an empty image");
    Image im(int(a.shape(1)), int(a.shape(0)));
    const double* p = a.data();
    for (py::ssize_t i = 0; i < a.size(); ++i) {
        const double v = p[i];
        if (std::isfinite(v) && std::abs(v) > double(std::numeric_limits<float>::max())) {
            const py::ssize_t pixel = i / 3, x = pixel % a.shape(1), y = pixel / a.shape(1);
            throw Error(name + ": value " + std::to_string(v) + " at [" + std::to_string(y) + ", " + std::to_string(x) +
                        ", " + std::to_string(i % 3) + "] is beyond float32's range (+-3.4e38), which images hold");
        }
        im.rgb[size_t(i)] = float(v);
    }
    if (const size_t bad = finite_only ? count_nonfinite_pixels(im) : 0)
        throw Error(name + ": " + std::to_string(bad) + " of " + std::to_string(size_t(im.width) * size_t(im.height)) +
                    " pixels are NaN or Inf; the error against the reference is undefined");
    return im;
}

double nan_if(bool unknown, double v) { return unknown ? std::numeric_limits<double>::quiet_NaN() : v; }

py::array_t<float> to_array(const Image& im) {
    py::array_t<float> out({size_t(im.height), size_t(im.width), size_t(3)});
    std::copy(im.rgb.begin(), im.rgb.end(), out.mutable_data());
    return out;
}

PixelRect to_rect(const std::vector<int>& v, const std::string& what) {
    if (v.size() != 4) throw Error(what + ": expected (x0, y0, x1, y1), got " + std::to_string(v.size()) + " numbers");
    std::string text;
    for (size_t i = 0; i < 4; ++i) text += (i ? "," : "") + std::to_string(v[i]);
    return parse_pixel_rect(text, what);
}

// Per image: the named metric (noise floor subtracted when `variance` is given), the channel-wise
// and luminance errors; over all of them as repeats (two or more): the repeat metrics.
py::dict compare(const std::vector<py::object>& images, const py::object& reference, const std::string& metric_name_text,
                 double epsilon, const std::optional<std::vector<int>>& crop, const std::vector<std::vector<int>>& excludes,
                 const std::optional<py::object>& mask_image, const std::optional<py::object>& variance_image) {
    if (images.empty()) throw Error("compare: no images");
    const Image ref = to_image(reference, "reference");
    MetricOptions metric;
    metric.metric = parse_error_metric(metric_name_text);
    metric.epsilon = epsilon;
    PixelMask mask(ref.width, ref.height);
    if (crop) mask.crop(to_rect(*crop, "crop"));
    for (const auto& e : excludes) mask.exclude(to_rect(e, "exclude"));
    if (mask_image) mask.intersect(to_image(*mask_image, "mask"), "mask");
    metric.mask = &mask;
    std::optional<Image> variance;
    if (variance_image) {
        variance = to_image(*variance_image, "reference_variance");
        if (variance->width != ref.width || variance->height != ref.height)
            throw Error("reference_variance: " + std::to_string(variance->width) + "x" + std::to_string(variance->height) +
                        ", but the reference is " + std::to_string(ref.width) + "x" + std::to_string(ref.height));
    }
    std::vector<Image> ims;
    for (size_t i = 0; i < images.size(); ++i) {
        ims.push_back(to_image(images[i], "image " + std::to_string(i)));
        if (ims.back().width != ref.width || ims.back().height != ref.height)
            throw Error("image " + std::to_string(i) + ": " + std::to_string(ims.back().width) + "x" +
                        std::to_string(ims.back().height) + ", but the reference is " + std::to_string(ref.width) + "x" +
                        std::to_string(ref.height));
    }
    py::list per_image;
    std::vector<const Image*> ptrs;
    std::vector<double> errors;
    for (const Image& im : ims) {
        const MetricValue m = measure_error(im, ref, metric, variance ? &*variance : nullptr);
        errors.push_back(m.value);
        const RunError y = run_error(im, ref);
        const ImageError e = compare_images(im, ref);
        py::dict d;
        d["error"] = m.value;
        d["error_raw"] = m.raw;
        d["noise_floor"] = m.floor;
        d["rel_rmse"] = y.rel_rmse;
        d["rel_bias"] = y.rel_mean_error;
        d["nonfinite_pixels"] = y.nonfinite_pixels;
        d["pixels"] = y.pixels;
        d["rgb_rmse"] = e.rmse;
        d["rgb_relative_rmse"] = e.relative_rmse;
        d["rgb_relative_bias"] = e.relative_bias;
        d["mean"] = e.mean;
        per_image.append(d);
        ptrs.push_back(&im);
    }
    const RepeatError r = repeat_error(ptrs, ref);
    py::dict out;
    // The named metric: its mean over the images and that mean's standard error (NaN for one image).
    double mean = 0, var = 0;
    for (double e : errors) mean += e / double(errors.size());
    for (double e : errors) var += errors.size() > 1 ? (e - mean) * (e - mean) / double(errors.size() - 1) : 0.0;
    out["metric"] = metric_name(metric.metric);
    out["metric_formula"] = metric_formula(metric.metric, metric.epsilon);
    out["mask"] = mask.describe();
    out["pixels"] = mask.compared_count();
    out["error"] = mean;
    out["error_se"] = nan_if(errors.size() < 2, std::sqrt(var / double(errors.size())));
    out["noise_floor"] = variance ? measure_error(ims[0], ref, metric, &*variance).floor : std::numeric_limits<double>::quiet_NaN();
    out["images"] = per_image;
    out["reference_luminance"] = reference_scale(ref);
    out["repeats"] = r.repeats;
    out["rel_rmse"] = r.rel_rmse;
    out["rel_mse"] = r.rel_mse;
    out["rel_bias"] = r.rel_bias;
    out["rel_bias_se"] = nan_if(r.repeats < 2, r.rel_bias_se);
    out["rel_bias2"] = r.rel_bias2;
    out["rel_variance"] = nan_if(r.repeats < 2, r.rel_variance);
    out["rel_std"] = nan_if(r.repeats < 2, r.rel_std);
    out["nonfinite_pixels"] = r.nonfinite_pixels;
    return out;
}

py::array luminance_of(const py::object& image) {
    const Image im = to_image(image, "image", false);
    py::array_t<double> out({size_t(im.height), size_t(im.width)});
    double* o = out.mutable_data();
    for (size_t p = 0; p < size_t(im.width) * size_t(im.height); ++p)
        o[p] = luminance(im.rgb[3 * p], im.rgb[3 * p + 1], im.rgb[3 * p + 2]);
    return out;
}

// 1.0 where the config's scene shows no area light, 0.0 where it does (seen_lights.h): a mask for
// compare's `mask`. width, height: the images' size (default: the config's).
py::array_t<double> exclude_lights_mask(const Config& config, std::optional<int> width, std::optional<int> height) {
    const int w = width.value_or(config.run->render.width), h = height.value_or(config.run->render.height);
    std::vector<uint8_t> seen;
    call_native([&](const std::atomic<bool>&) { seen = seen_light_pixels(*config.run->scene, w, h); });
    py::array_t<double> out({size_t(h), size_t(w)});
    double* o = out.mutable_data();
    for (size_t p = 0; p < seen.size(); ++p) o[p] = seen[p] ? 0.0 : 1.0;
    return out;
}

}  // namespace

void bind_compare(py::module_& m) {
    m.def("_compare", &compare, py::arg("images"), py::arg("reference"), py::arg("metric"), py::arg("epsilon"),
          py::arg("crop"), py::arg("exclude"), py::arg("mask"), py::arg("reference_variance"));
    m.def(
        "_reference_from_halves",
        [](const py::object& a, const py::object& b) {
            const NoisyReference r = reference_from_halves(to_image(a, "half A"), to_image(b, "half B"), "halves");
            return py::make_tuple(to_array(r.image), to_array(*r.variance));
        },
        py::arg("a"), py::arg("b"));
    m.def("_more_samples_warning", &more_samples_warning, py::arg("run"), py::arg("run_samples"), py::arg("reference"),
          py::arg("reference_samples"));
    m.def("exclude_lights_mask", &exclude_lights_mask, py::arg("config"), py::arg("width") = py::none(),
          py::arg("height") = py::none(),
          "A (height, width) float64 array, 1.0 where the config's scene shows no area light and 0.0 where a camera ray "
          "meets one, straight or through mirrors and glass (lib/analysis/metrics/seen_lights.h): pass it as "
          "vpm.compare's mask= to leave directly seen lights out. width, height: the images' size (default: the "
          "config's; the same aspect ratio).");
    m.def("luminance", &luminance_of, py::arg("image"),
          "Luminance Y = 0.2126 R + 0.7152 G + 0.0722 B of an (height, width, 3) image, as a float64 (height, width) "
          "array: what vpm.compare and sweeps compare.");
}

}  // namespace vpm::python
