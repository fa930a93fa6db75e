#include "analysis/image_compare.h"

#include <cmath>

#include "core/error.h"

namespace vpm {

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
