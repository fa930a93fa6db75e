#include "analysis/metrics/pixel_mask.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/error.h"

namespace vpm {

namespace {

std::string rect_text(const PixelRect& r) {
    return std::to_string(r.x0) + "," + std::to_string(r.y0) + "," + std::to_string(r.x1) + "," + std::to_string(r.y1);
}

}  // namespace

PixelRect parse_pixel_rect(const std::string& text, const std::string& what) {
    std::istringstream in(text);
    PixelRect r;
    char c1 = 0, c2 = 0, c3 = 0;
    if (!(in >> r.x0 >> c1 >> r.y0 >> c2 >> r.x1 >> c3 >> r.y1) || c1 != ',' || c2 != ',' || c3 != ',' || !(in >> std::ws).eof())
        throw Error(what + ": expected X0,Y0,X1,Y1 (pixels, half-open), got '" + text + "'");
    if (r.x0 < 0 || r.y0 < 0 || r.x1 <= r.x0 || r.y1 <= r.y0)
        throw Error(what + ": '" + text + "' needs 0 <= X0 < X1 and 0 <= Y0 < Y1");
    return r;
}

PixelMask::PixelMask(int width, int height)
    : width_(width), height_(height), keep_(size_t(std::max(width, 0)) * size_t(std::max(height, 0)), 1) {}

size_t PixelMask::compared_count() const { return size_t(std::count(keep_.begin(), keep_.end(), uint8_t(1))); }

void PixelMask::crop(const PixelRect& r) {
    for (int y = 0; y < height_; ++y)
        for (int x = 0; x < width_; ++x)
            if (x < r.x0 || x >= r.x1 || y < r.y0 || y >= r.y1) keep_[size_t(y) * size_t(width_) + size_t(x)] = 0;
    steps_.push_back("crop " + rect_text(r));
    if (compared_count() == 0)
        throw Error("crop " + rect_text(r) + ": no pixel of the " + std::to_string(width_) + "x" + std::to_string(height_) +
                    " image is left");
}

void PixelMask::exclude(const PixelRect& r) {
    for (int y = std::max(r.y0, 0); y < std::min(r.y1, height_); ++y)
        for (int x = std::max(r.x0, 0); x < std::min(r.x1, width_); ++x) keep_[size_t(y) * size_t(width_) + size_t(x)] = 0;
    steps_.push_back("exclude " + rect_text(r));
}

void PixelMask::intersect(const Image& mask, const std::string& name) {
    if (mask.width != width_ || mask.height != height_)
        throw Error(name + ": the mask is " + std::to_string(mask.width) + "x" + std::to_string(mask.height) +
                    ", the images " + std::to_string(width_) + "x" + std::to_string(height_));
    for (size_t p = 0; p < keep_.size(); ++p)
        if (mask.rgb[3 * p] == 0.0f && mask.rgb[3 * p + 1] == 0.0f && mask.rgb[3 * p + 2] == 0.0f) keep_[p] = 0;
    steps_.push_back("mask " + name);
}

void PixelMask::exclude_marked(const std::vector<uint8_t>& marked, const std::string& step) {
    if (marked.size() != keep_.size())
        throw Error(step + ": " + std::to_string(marked.size()) + " pixels marked, the images have " + std::to_string(keep_.size()));
    for (size_t p = 0; p < keep_.size(); ++p)
        if (marked[p]) keep_[p] = 0;
    steps_.push_back(step);
}

std::string PixelMask::describe() const {
    const size_t total = keep_.size();
    if (steps_.empty()) return "all " + std::to_string(total) + " pixels";
    std::string s = std::to_string(compared_count()) + " of " + std::to_string(total) + " pixels (";
    for (size_t i = 0; i < steps_.size(); ++i) s += (i ? ", " : "") + steps_[i];
    return s + ")";
}

}  // namespace vpm
