// OpenEXR reading (io/exr_read.h). The only reader of EXR files in vpm; render/run/image_io.cpp
// writes them.
#include "io/exr_read.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfTestFile.h>

#include <cstdint>
#include <string>

#include "core/error.h"

namespace fs = std::filesystem;

namespace vpm {
namespace {

[[noreturn]] void fail(const fs::path& path, const std::string& reason) {
    throw FileError(path.string() + ": " + reason);
}

}  // namespace

ExrPixels read_exr_pixels(const fs::path& path) {
    std::error_code ec;
    if (!fs::exists(path, ec)) fail(path, "cannot read: file does not exist");
    if (fs::is_directory(path, ec)) fail(path, "cannot read: it is a folder, not an OpenEXR file");
    bool tiled = false;
    if (!Imf::isOpenExrFile(path.c_str(), tiled)) fail(path, "cannot read: not an OpenEXR file");
    try {
        Imf::InputFile file(path.c_str());
        const Imf::Header& header = file.header();
        const Imath::Box2i dw = header.dataWindow();
        const int64_t w = int64_t(dw.max.x) - dw.min.x + 1;
        const int64_t h = int64_t(dw.max.y) - dw.min.y + 1;
        if (w <= 0 || h <= 0 || w > (1 << 20) || h > (1 << 20))
            fail(path, "OpenEXR data window has an invalid size " + std::to_string(w) + " x " +
                           std::to_string(h));
        std::string missing;
        for (const char* name : {"R", "G", "B"})
            if (!header.channels().findChannel(name)) missing += std::string(missing.empty() ? "" : ", ") + name;
        if (!missing.empty()) {
            std::string present;
            for (auto it = header.channels().begin(); it != header.channels().end(); ++it)
                present += std::string(present.empty() ? "" : ", ") + it.name();
            fail(path, "OpenEXR file lacks channel(s) " + missing + " (it has: " +
                           (present.empty() ? std::string("none") : present) + "); R, G and B are required");
        }

        ExrPixels image;
        image.width = static_cast<int>(w);
        image.height = static_cast<int>(h);
        image.rgb.assign(size_t(3) * size_t(w) * size_t(h), 0.0f);
        const size_t xs = 3 * sizeof(float);
        const size_t ys = xs * size_t(w);
        char* base = reinterpret_cast<char*>(image.rgb.data());
        Imf::FrameBuffer fb;   // HALF or UINT channels are converted to FLOAT by the library
        fb.insert("R", Imf::Slice::Make(Imf::FLOAT, base + 0 * sizeof(float), dw, xs, ys));
        fb.insert("G", Imf::Slice::Make(Imf::FLOAT, base + 1 * sizeof(float), dw, xs, ys));
        fb.insert("B", Imf::Slice::Make(Imf::FLOAT, base + 2 * sizeof(float), dw, xs, ys));
        file.setFrameBuffer(fb);
        file.readPixels(dw.min.y, dw.max.y);
        return image;
    } catch (const FileError&) {
        throw;
    } catch (const std::exception& e) {
        fail(path, std::string("cannot read OpenEXR file: ") + e.what());
    }
}

}  // namespace vpm
