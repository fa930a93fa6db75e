#include "analysis/metrics/error_metrics.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>

#include "core/error.h"
#include "render/plan/relative_error.h"

namespace vpm {

// The auto plan minimises this relMSE (render/plan/relative_error.h): one epsilon for both.
static_assert(kDefaultMetricEpsilon == kRelativeErrorEpsilon, "the plan's relative error is the relMSE");

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

ErrorMetric parse_error_metric(const std::string& name) {
    std::string n;
    for (char c : name)
        if (c != '_' && c != '-') n += char(std::tolower(static_cast<unsigned char>(c)));
    if (n == "relmse") return ErrorMetric::rel_mse;
    if (n == "relrmse") return ErrorMetric::rel_rmse;
    if (n == "smape") return ErrorMetric::smape;
    throw Error("metric '" + name + "' is not known (allowed: relmse, relrmse, smape)");
}

std::string metric_name(ErrorMetric metric) {
    switch (metric) {
        case ErrorMetric::rel_mse: return "relMSE";
        case ErrorMetric::rel_rmse: return "relRMSE";
        case ErrorMetric::smape: return "SMAPE";
    }
    throw Error("metric_name: unknown metric");
}

std::string metric_formula(ErrorMetric metric, double epsilon) {
    std::ostringstream eps;
    eps << epsilon;
    switch (metric) {
        case ErrorMetric::rel_mse: return "relMSE = mean (I - R)^2 / (R^2 + " + eps.str() + ") over luminance";
        case ErrorMetric::rel_rmse: return "relRMSE = sqrt(mean (I - R)^2) / mean R over luminance";
        case ErrorMetric::smape: return "SMAPE = mean |I - R| / (|I| + |R| + " + eps.str() + ") over luminance";
    }
    throw Error("metric_formula: unknown metric");
}

bool metric_has_floor(ErrorMetric metric) { return metric != ErrorMetric::smape; }

bool MetricValue::floor_known() const { return std::isfinite(floor); }

MetricValue measure_error(const Image& image, const Image& reference, const MetricOptions& o, const Image* variance) {
    check_size(image, reference);
    if (variance) check_size(*variance, reference);
    if (o.mask && (o.mask->width() != reference.width || o.mask->height() != reference.height))
        throw Error("the mask is " + std::to_string(o.mask->width()) + "x" + std::to_string(o.mask->height()) +
                    " but the reference is " + std::to_string(reference.width) + "x" + std::to_string(reference.height));
    if (!(o.epsilon > 0) || !std::isfinite(o.epsilon))
        throw Error("metric epsilon " + std::to_string(o.epsilon) + ": must be a finite number > 0");
    const size_t n = size_t(reference.width) * size_t(reference.height);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    MetricValue m;
    m.metric = o.metric;
    m.epsilon = o.epsilon;
    // Sums over the compared pixels: the error term, the floor term, and the reference's luminance.
    double err = 0, noise = 0, ref_sum = 0;
    for (size_t p = 0; p < n; ++p) {
        if (o.mask && !o.mask->compared(p)) {
            ++m.masked_out;
            continue;
        }
        if (!finite_pixel(reference, p))
            throw Error("the reference image has a non-finite pixel (" + std::to_string(p % size_t(reference.width)) + ", " +
                        std::to_string(p / size_t(reference.width)) + ")");
        if (!finite_pixel(image, p)) {
            ++m.nonfinite_pixels;
            continue;
        }
        const double r = lum(reference, p), i = lum(image, p), d = i - r;
        const double v = variance ? double(variance->rgb[3 * p]) : 0.0;
        ++m.pixels;
        ref_sum += r;
        switch (o.metric) {
            case ErrorMetric::rel_mse:
                err += d * d / (r * r + o.epsilon);
                noise += v / (r * r + o.epsilon);
                break;
            case ErrorMetric::rel_rmse:
                err += d * d;
                noise += v;
                break;
            case ErrorMetric::smape:
                err += std::abs(d) / (std::abs(i) + std::abs(r) + o.epsilon);
                break;
        }
    }
    if (m.pixels == 0) throw Error("no pixel to compare (" + std::to_string(m.masked_out) + " masked out, " +
                                   std::to_string(m.nonfinite_pixels) + " non-finite)");
    const double P = double(m.pixels);
    switch (o.metric) {
        case ErrorMetric::rel_mse:
            m.raw = err / P;
            m.floor = variance ? noise / P : nan;
            m.value = variance ? m.raw - m.floor : m.raw;
            break;
        case ErrorMetric::rel_rmse: {
            const double L = ref_sum / P;
            if (!(L > 0)) throw Error("the reference's mean luminance over the compared pixels is " + std::to_string(L) +
                                      "; relRMSE needs a positive mean");
            m.raw = std::sqrt(err / P) / L;
            m.floor = variance ? std::sqrt(noise / P) / L : nan;
            const double d = m.raw * m.raw - (variance ? m.floor * m.floor : 0.0);
            m.value = d < 0 ? -std::sqrt(-d) : std::sqrt(d);
            break;
        }
        case ErrorMetric::smape:
            m.raw = m.value = err / P;
            m.floor = nan;
            break;
    }
    return m;
}

std::string describe(const MetricValue& v) {
    std::ostringstream s;
    s.precision(4);
    s << metric_name(v.metric) << " " << v.value;
    if (v.floor_known())
        s << " (raw " << v.raw << " - reference noise floor " << v.floor << ")";
    else if (metric_has_floor(v.metric))
        s << " (reference noise unknown: not subtracted)";
    else
        s << " (no noise floor: not a squared error)";
    if (v.nonfinite_pixels) s << ", " << v.nonfinite_pixels << " NON-FINITE pixels left out";
    return s.str();
}

}  // namespace vpm
