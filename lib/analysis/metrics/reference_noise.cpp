#include "analysis/metrics/reference_noise.h"

#include "analysis/metrics/error_metrics.h"
#include "core/error.h"
#include "render/run/image_io.h"

namespace vpm {

namespace fs = std::filesystem;

namespace {

void check_same_size(const Image& a, const std::string& a_name, const Image& b, const std::string& b_name) {
    if (a.width != b.width || a.height != b.height)
        throw Error(a_name + " is " + std::to_string(a.width) + "x" + std::to_string(a.height) + " but " + b_name + " is " +
                    std::to_string(b.width) + "x" + std::to_string(b.height));
}

}  // namespace

fs::path variance_path_for(const fs::path& exr) {
    fs::path p = exr;
    p.replace_extension(".variance.exr");
    return p;
}

NoisyReference load_reference(const fs::path& exr, const fs::path& variance_file) {
    NoisyReference r;
    r.image = read_exr(exr);
    r.name = exr.string();
    const fs::path v = variance_file.empty() ? variance_path_for(exr) : variance_file;
    if (!variance_file.empty() && !fs::exists(v)) throw FileError(v.string() + ": no such variance image");
    if (fs::exists(v)) {
        r.variance = read_exr(v);
        check_same_size(*r.variance, v.string(), r.image, exr.string());
        r.noise_source = v.string();
    }
    return r;
}

NoisyReference reference_from_halves(const Image& a, const Image& b, const std::string& name) {
    check_same_size(a, "the first half", b, "the second half");
    NoisyReference r;
    r.name = name;
    r.noise_source = "the difference of the halves " + name;
    r.image = Image(a.width, a.height);
    Image var(a.width, a.height);
    for (size_t p = 0; p < size_t(a.width) * size_t(a.height); ++p) {
        for (int c = 0; c < 3; ++c) r.image.rgb[3 * p + c] = 0.5f * (a.rgb[3 * p + c] + b.rgb[3 * p + c]);
        const double d = 0.5 * (luminance(a.rgb[3 * p], a.rgb[3 * p + 1], a.rgb[3 * p + 2]) -
                                luminance(b.rgb[3 * p], b.rgb[3 * p + 1], b.rgb[3 * p + 2]));
        for (int c = 0; c < 3; ++c) var.rgb[3 * p + c] = float(d * d);
    }
    r.variance = std::move(var);
    return r;
}

NoisyReference load_reference_halves(const fs::path& a, const fs::path& b) {
    const Image ia = read_exr(a), ib = read_exr(b);
    check_same_size(ia, a.string(), ib, b.string());
    return reference_from_halves(ia, ib, a.string() + " + " + b.string());
}

}  // namespace vpm
