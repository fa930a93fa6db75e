#pragma once
// Which pixels an error metric compares (error_metrics.h): all by default; a crop rectangle keeps
// only the pixels inside it, excluded rectangles leave theirs out (a light's glint, a directly seen
// lamp), and a mask image keeps the pixels where it is non-zero. Rectangles are in pixels,
// half-open [x0, x1) x [y0, y1), row 0 at the top (as the EXR).
#include <cstdint>
#include <string>
#include <vector>

#include "render/run/image.h"

namespace vpm {

struct PixelRect {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
};

// "X0,Y0,X1,Y1" with 0 <= X0 < X1 and 0 <= Y0 < Y1; throws vpm::Error naming `what` otherwise.
PixelRect parse_pixel_rect(const std::string& text, const std::string& what);

class PixelMask {
public:
    PixelMask() = default;
    PixelMask(int width, int height);   // every pixel compared

    int width() const { return width_; }
    int height() const { return height_; }
    bool compared(size_t pixel) const { return keep_[pixel] != 0; }
    size_t compared_count() const;

    // Keep only the pixels inside `r` (clipped to the image; throws vpm::Error when nothing is left).
    void crop(const PixelRect& r);
    // Leave out the pixels inside `r` (clipped to the image).
    void exclude(const PixelRect& r);
    // Leave out the pixels where `mask` is zero in every channel; throws vpm::Error naming `name`
    // when its size differs.
    void intersect(const Image& mask, const std::string& name);
    // Leave out the pixels where `marked` (one byte per pixel) is non-zero; `step` describes it.
    // Throws vpm::Error when its size differs.
    void exclude_marked(const std::vector<uint8_t>& marked, const std::string& step);

    // A one-line description for reports ("all 4096 pixels", "3900 of 4096 pixels: crop ..., exclude ...").
    std::string describe() const;

private:
    int width_ = 0, height_ = 0;
    std::vector<uint8_t> keep_;
    std::vector<std::string> steps_;
};

}  // namespace vpm
