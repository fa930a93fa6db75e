#pragma once
// Reading OpenEXR images below the render layer: scene files such as environment maps are EXR.
// render/run/image_io.h's read_exr returns the same pixels as an Image (writing stays in render/).
#include <filesystem>
#include <vector>

namespace vpm {

// Linear RGB float pixels, row-major, row 0 at the top.
struct ExrPixels {
    int width = 0;
    int height = 0;
    std::vector<float> rgb;   // 3 * width * height
};

// Accepts any EXR with R, G and B channels (HALF/UINT are converted to float) and honours a data
// window that does not start at (0, 0). Throws FileError "<path>: ..." for a missing file, a
// folder, a file that is not OpenEXR, a truncated file, missing channels or an invalid size.
ExrPixels read_exr_pixels(const std::filesystem::path& path);

}  // namespace vpm
