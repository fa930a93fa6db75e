#pragma once
// An RGB float image in linear radiance, row-major, row 0 at the top.
#include <string>
#include <vector>

#include "core/math.h"

namespace vpm {

struct Image {
    int width = 0;
    int height = 0;
    std::vector<float> rgb;   // 3 * width * height

    Image() = default;
    Image(int w, int h) : width(w), height(h), rgb(size_t(3) * size_t(w) * size_t(h), 0.0f) {}
    // Mean over pixels and channels, summed in double (0 for an empty image).
    double mean() const {
        double sum = 0.0;
        for (float v : rgb) sum += double(v);
        return rgb.empty() ? 0.0 : sum / double(rgb.size());
    }
    Rgb at(int x, int y) const {
        const size_t i = 3 * (size_t(y) * size_t(width) + size_t(x));
        return Rgb(rgb[i], rgb[i + 1], rgb[i + 2]);
    }
    void set(int x, int y, const Rgb& c) {
        const size_t i = 3 * (size_t(y) * size_t(width) + size_t(x));
        rgb[i] = float(c[0]); rgb[i + 1] = float(c[1]); rgb[i + 2] = float(c[2]);
    }
};

}  // namespace vpm
