#pragma once
// Image files. Writers are atomic: they write "<path>.tmp-<pid>" and rename it over `path`, so
// a failed or interrupted write never leaves a partial file and never destroys an old one.
#include <filesystem>
#include <string>

#include "render/image.h"

namespace vpm {

// OpenEXR, RGB 32-bit float, no compression loss. Throws FileError naming the path.
void write_exr(const std::filesystem::path& path, const Image& image);
Image read_exr(const std::filesystem::path& path);

// 8-bit sRGB PNG preview: pixel * 2^exposure, then clamp to [0, 1] (display only) and the sRGB
// curve. Throws FileError.
void write_png_preview(const std::filesystem::path& path, const Image& image, double exposure = 0.0);

// Writes text atomically (same rule as the images); for JSON sidecars and tables.
void write_text_atomic(const std::filesystem::path& path, const std::string& text);

}  // namespace vpm
