#include "analysis/error_metrics.h"

#include <cmath>
#include <limits>
#include <string>

#include "core/error.h"

namespace vpm {

namespace {

bool finite_pixel(const Image& im, size_t p) {
    return std::isfinite(im.rgb[3 * p]) && std::isfinite(im.rgb[3 * p + 1]) && std::isfinite(im.rgb[3 * p + 2]);
}

double lum(const Image& im, size_t p) { return luminance(im.rgb[3 * p], im.rgb[3 * p + 1], im.rgb[3 * p + 2]); }

void check_size(const Image& im, const Image& ref) {
    if (im.width != ref.width || im.height != ref.height)
        throw Error("image is " + std::to_string(im.width) + "x" + std::to_string(im.height) + " but the reference is " +
                    std::to_string(ref.width) + "x" + std::to_string(ref.height));
}

}  // namespace

double luminance(float r, float g, float b) { return 0.2126 * r + 0.7152 * g + 0.0722 * b; }

double reference_scale(const Image& reference) {
    const size_t n = size_t(reference.width) * size_t(reference.height);
    if (n == 0) throw Error("the reference image is empty");
    double sum = 0;
    for (size_t p = 0; p < n; ++p) {
        if (!finite_pixel(reference, p)) throw Error("the reference image has a non-finite pixel (" +
                                                     std::to_string(p % size_t(reference.width)) + ", " +
                                                     std::to_string(p / size_t(reference.width)) + ")");
        sum += lum(reference, p);
    }
    const double mean = sum / double(n);
    if (!(mean > 0)) throw Error("the reference image has mean luminance " + std::to_string(mean) +
                                 "; relative errors need a positive mean");
    return mean;
}

RunError run_error(const Image& image, const Image& reference) {
    check_size(image, reference);
    const double L = reference_scale(reference);
    const size_t n = size_t(reference.width) * size_t(reference.height);
    RunError e;
    double s1 = 0, s2 = 0;
    for (size_t p = 0; p < n; ++p) {
        if (!finite_pixel(image, p)) {
            ++e.nonfinite_pixels;
            continue;
        }
        const double d = lum(image, p) - lum(reference, p);
        s1 += d;
        s2 += d * d;
        ++e.pixels;
    }
    const double m = e.pixels ? 1.0 / double(e.pixels) : std::numeric_limits<double>::quiet_NaN();
    e.rel_rmse = std::sqrt(s2 * m) / L;
    e.rel_mean_error = s1 * m / L;
    return e;
}

RepeatError repeat_error(const std::vector<const Image*>& images, const Image& reference) {
    if (images.empty()) throw Error("repeat_error: no images");
    for (const Image* im : images) check_size(*im, reference);
    const double L = reference_scale(reference);
    const size_t n = size_t(reference.width) * size_t(reference.height);
    const size_t R = images.size();
    const double nan = std::numeric_limits<double>::quiet_NaN();
    RepeatError e;
    e.repeats = R;
    std::vector<double> per_repeat(R, 0.0);   // sum_p (I_rp - R_p)
    double sq = 0, bias2 = 0, var = 0;
    std::vector<double> y(R);
    for (size_t p = 0; p < n; ++p) {
        bool ok = true;
        for (size_t r = 0; r < R; ++r) {
            if (!finite_pixel(*images[r], p)) {
                ++e.nonfinite_pixels;
                ok = false;
            }
        }
        if (!ok) continue;
        ++e.pixels;
        const double ref = lum(reference, p);
        double mean = 0;
        for (size_t r = 0; r < R; ++r) {
            y[r] = lum(*images[r], p) - ref;
            mean += y[r];
            per_repeat[r] += y[r];
            sq += y[r] * y[r];
        }
        mean /= double(R);
        double s2 = 0;
        if (R > 1) {
            for (size_t r = 0; r < R; ++r) s2 += (y[r] - mean) * (y[r] - mean);
            s2 /= double(R - 1);
        }
        var += s2;
        bias2 += mean * mean - s2 / double(R);
    }
    if (e.pixels == 0) {
        e.rel_rmse = e.rel_mse = e.rel_bias = e.rel_bias_se = e.rel_bias2 = e.rel_variance = e.rel_std = nan;
        return e;
    }
    const double P = double(e.pixels), L2 = L * L;
    e.rel_mse = sq / (double(R) * P) / L2;
    e.rel_rmse = std::sqrt(e.rel_mse);
    e.rel_bias2 = bias2 / P / L2;
    double mb = 0;
    for (double& b : per_repeat) {
        b = b / P / L;
        mb += b;
    }
    mb /= double(R);
    e.rel_bias = mb;
    if (R > 1) {
        double v = 0;
        for (double b : per_repeat) v += (b - mb) * (b - mb);
        v /= double(R - 1);
        e.rel_bias_se = std::sqrt(v / double(R));
        e.rel_variance = var / P / L2;
        e.rel_std = std::sqrt(e.rel_variance);
    } else {
        e.rel_bias_se = e.rel_variance = e.rel_std = nan;
    }
    return e;
}

ImageError compare_images(const Image& a, const Image& r) {
    if (a.width != r.width || a.height != r.height)
        throw Error("compare_images: image is " + std::to_string(a.width) + "x" + std::to_string(a.height) +
                    " but the reference is " + std::to_string(r.width) + "x" + std::to_string(r.height));
    ImageError e;
    double sa = 0, sr = 0, se = 0;
    size_t n = 0;
    for (size_t i = 0; i < a.rgb.size(); ++i) {
        const double x = a.rgb[i], y = r.rgb[i];
        if (!std::isfinite(x) || !std::isfinite(y)) {
            ++e.nonfinite;
            continue;
        }
        sa += x;
        sr += y;
        se += (x - y) * (x - y);
        ++n;
    }
    if (n == 0) return e;
    e.mean = sa / double(n);
    e.reference_mean = sr / double(n);
    e.rmse = std::sqrt(se / double(n));
    e.relative_rmse = e.reference_mean > 0 ? e.rmse / e.reference_mean : 0.0;
    e.relative_bias = e.reference_mean > 0 ? e.mean / e.reference_mean - 1.0 : 0.0;
    return e;
}

}  // namespace vpm
