#pragma once
// Image files. Writers are atomic (render/run/staged_file.h): they write "<path>.tmp-<pid>-<n>" and
// rename it over `path`, so a failed or interrupted write never leaves a partial file and never
// destroys an old one. A missing folder, a parent that is not a folder, or a target that is not a
// regular file (folder, device, FIFO, socket) is refused with FileError; symlinks are written
// through. The stage_* forms write the temporary and leave the rename to the caller, so that
// several files can be committed together (commit_together).
#include <filesystem>
#include <string>

#include "render/run/image.h"
#include "render/run/staged_file.h"

namespace vpm {

// OpenEXR, RGB 32-bit float, ZIP (lossless) compression. Throws FileError naming the path.
// read_exr is io/exr_read.h's reader (any EXR with R, G and B channels, HALF/UINT converted to
// float, a data window that need not start at (0, 0)) returning an Image.
void write_exr(const std::filesystem::path& path, const Image& image);
StagedFile stage_exr(const std::filesystem::path& path, const Image& image);
Image read_exr(const std::filesystem::path& path);

// 8-bit sRGB PNG preview: pixel * 2^exposure, then clamp to [0, 1] (display only) and the sRGB
// curve. Pixels with a NaN channel are shown magenta. Throws FileError.
void write_png_preview(const std::filesystem::path& path, const Image& image, double exposure = 0.0);
StagedFile stage_png_preview(const std::filesystem::path& path, const Image& image, double exposure = 0.0);

// Writes text atomically (same rule as the images); for JSON sidecars and tables.
void write_text_atomic(const std::filesystem::path& path, const std::string& text);
StagedFile stage_text(const std::filesystem::path& path, const std::string& text);

}  // namespace vpm
