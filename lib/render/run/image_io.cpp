// Image files: OpenEXR (lossless float), PNG previews (libpng simplified API), atomic text.
// Every writer stages a StagedFile (render/run/staged_file.h): the data goes to a unique temporary
// beside the destination, which is renamed over it only on commit; on any failure the temporary
// is removed and the destination is left exactly as it was.
#include "render/run/image_io.h"

#include <png.h>
#include <unistd.h>

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfOutputFile.h>

#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <system_error>

#include "core/error.h"
#include "render/run/staged_file.h"
#include "io/exr_read.h"

namespace fs = std::filesystem;

namespace vpm {
namespace {

[[noreturn]] void fail(const fs::path& path, const std::string& reason) {
    throw FileError(path.string() + ": " + reason);
}

void check_image(const fs::path& path, const Image& image) {
    if (image.width <= 0 || image.height <= 0)
        fail(path, "cannot write an empty image (" + std::to_string(image.width) + " x " +
                       std::to_string(image.height) + ")");
    const size_t expected = size_t(3) * size_t(image.width) * size_t(image.height);
    if (image.rgb.size() != expected)
        fail(path, "cannot write: image is " + std::to_string(image.width) + " x " +
                       std::to_string(image.height) + " but holds " + std::to_string(image.rgb.size()) +
                       " values, expected " + std::to_string(expected));
}

// Linear [0, 1] -> 8-bit sRGB code value (IEC 61966-2-1).
unsigned char srgb_encode(double v) {
    v = v <= 0.0 ? 0.0 : (v >= 1.0 ? 1.0 : v);
    const double s = v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055;
    return (unsigned char)std::lround(s * 255.0);
}

}  // namespace

StagedFile stage_exr(const fs::path& path, const Image& image) {
    check_image(path, image);
    StagedFile target(path);
    try {
        Imf::Header header(image.width, image.height);
        header.compression() = Imf::ZIP_COMPRESSION;
        header.channels().insert("R", Imf::Channel(Imf::FLOAT));
        header.channels().insert("G", Imf::Channel(Imf::FLOAT));
        header.channels().insert("B", Imf::Channel(Imf::FLOAT));

        const size_t xs = 3 * sizeof(float);
        const size_t ys = xs * size_t(image.width);
        char* base = reinterpret_cast<char*>(const_cast<float*>(image.rgb.data()));
        Imf::FrameBuffer fb;
        fb.insert("R", Imf::Slice(Imf::FLOAT, base + 0 * sizeof(float), xs, ys));
        fb.insert("G", Imf::Slice(Imf::FLOAT, base + 1 * sizeof(float), xs, ys));
        fb.insert("B", Imf::Slice(Imf::FLOAT, base + 2 * sizeof(float), xs, ys));

        Imf::OutputFile file(target.temp().c_str(), header);   // closed before the rename
        file.setFrameBuffer(fb);
        file.writePixels(image.height);
    } catch (const std::exception& e) {
        target.abort(std::string("cannot write OpenEXR file: ") + e.what());
    }
    return target;
}

void write_exr(const fs::path& path, const Image& image) { stage_exr(path, image).commit(); }

Image read_exr(const fs::path& path) {
    ExrPixels pixels = read_exr_pixels(path);
    Image image;
    image.width = pixels.width;
    image.height = pixels.height;
    image.rgb = std::move(pixels.rgb);
    return image;
}

StagedFile stage_png_preview(const fs::path& path, const Image& image, double exposure) {
    check_image(path, image);
    if (!std::isfinite(exposure)) fail(path, "PNG preview exposure must be finite");
    StagedFile target(path);

    const double scale = std::exp2(exposure);
    std::vector<unsigned char> pixels(image.rgb.size());
    for (size_t i = 0; i < image.rgb.size(); i += 3) {
        const float r = image.rgb[i], g = image.rgb[i + 1], b = image.rgb[i + 2];
        if (std::isnan(r) || std::isnan(g) || std::isnan(b)) {   // make bad pixels obvious
            pixels[i] = 255; pixels[i + 1] = 0; pixels[i + 2] = 255;
            continue;
        }
        pixels[i] = srgb_encode(r * scale);
        pixels[i + 1] = srgb_encode(g * scale);
        pixels[i + 2] = srgb_encode(b * scale);
    }

    png_image png;
    std::memset(&png, 0, sizeof(png));
    png.version = PNG_IMAGE_VERSION;
    png.width = png_uint_32(image.width);
    png.height = png_uint_32(image.height);
    png.format = PNG_FORMAT_RGB;   // 8-bit, non-linear: libpng writes an sRGB chunk
    const int ok = png_image_write_to_file(&png, target.temp().c_str(), 0, pixels.data(),
                                           png_int_32(3 * image.width), nullptr);
    if (!ok || PNG_IMAGE_FAILED(png)) {
        const std::string message = png.message[0] ? png.message : "unknown libpng error";
        png_image_free(&png);
        target.abort("cannot write PNG file: " + message);
    }
    png_image_free(&png);
    return target;
}

void write_png_preview(const fs::path& path, const Image& image, double exposure) {
    stage_png_preview(path, image, exposure).commit();
}

StagedFile stage_text(const fs::path& path, const std::string& text) {
    StagedFile target(path);
    const int fd = ::open(target.temp().c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
    if (fd < 0) {
        const int err = errno;
        target.abort(std::string("cannot write: ") + std::strerror(err));
    }
    const char* p = text.data();
    size_t left = text.size();
    while (left > 0) {
        const ssize_t n = ::write(fd, p, left);
        if (n < 0) {
            if (errno == EINTR) continue;
            const int err = errno;
            ::close(fd);
            target.abort(std::string("cannot write: ") + std::strerror(err));
        }
        p += n;
        left -= size_t(n);
    }
    if (::close(fd) != 0) {
        const int err = errno;
        target.abort(std::string("cannot write: ") + std::strerror(err));
    }
    return target;
}

void write_text_atomic(const fs::path& path, const std::string& text) { stage_text(path, text).commit(); }

}  // namespace vpm
