// Image files: OpenEXR (lossless float), PNG previews (libpng simplified API), atomic text.
// Every writer goes through AtomicTarget: write a unique temporary file in the destination
// folder, then rename it over the destination; on any failure the temporary is removed and the
// destination is left exactly as it was.
#include "render/image_io.h"

#include <png.h>
#include <unistd.h>

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfTestFile.h>

#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <system_error>

#include "core/error.h"

namespace fs = std::filesystem;

namespace vpm {
namespace {

std::string quoted(const fs::path& p) { return "'" + p.string() + "'"; }

[[noreturn]] void fail(const fs::path& path, const std::string& reason) {
    throw FileError(path.string() + ": " + reason);
}

// A temporary file beside `path`, renamed over it by commit(); removed on destruction otherwise.
class AtomicTarget {
public:
    explicit AtomicTarget(const fs::path& path) : path_(path) {
        if (path.empty()) throw FileError("(empty path): cannot write: no file name given");
        if (!path.has_filename()) fail(path, "cannot write: the path names a folder, not a file");
        const fs::path parent = path.parent_path().empty() ? fs::path(".") : path.parent_path();
        std::error_code ec;
        const fs::file_status st = fs::status(parent, ec);
        if (!fs::exists(st)) fail(path, "cannot write: folder " + quoted(parent) + " does not exist");
        if (!fs::is_directory(st)) fail(path, "cannot write: " + quoted(parent) + " is not a folder");
        if (fs::is_directory(path, ec)) fail(path, "cannot write: a folder of that name exists");

        static std::atomic<unsigned long> counter{0};
        temp_ = path;
        temp_ += ".tmp-" + std::to_string(long(::getpid())) + "-" + std::to_string(counter++);
    }
    AtomicTarget(const AtomicTarget&) = delete;
    AtomicTarget& operator=(const AtomicTarget&) = delete;
    ~AtomicTarget() {
        if (!committed_) {
            std::error_code ec;
            fs::remove(temp_, ec);
        }
    }

    const fs::path& temp() const { return temp_; }
    const fs::path& path() const { return path_; }

    // Removes the temporary and throws FileError naming the destination.
    [[noreturn]] void abort(const std::string& reason) {
        std::error_code ec;
        fs::remove(temp_, ec);
        committed_ = true;   // nothing left to clean up
        fail(path_, reason);
    }

    void commit() {
        if (std::rename(temp_.c_str(), path_.c_str()) != 0) {
            const int err = errno;
            abort(std::string("cannot write: rename from temporary file failed: ") + std::strerror(err));
        }
        committed_ = true;
    }

private:
    fs::path path_;
    fs::path temp_;
    bool committed_ = false;
};

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

void write_exr(const fs::path& path, const Image& image) {
    check_image(path, image);
    AtomicTarget target(path);
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
    target.commit();
}

Image read_exr(const fs::path& path) {
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

        Image image(static_cast<int>(w), static_cast<int>(h));
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

void write_png_preview(const fs::path& path, const Image& image, double exposure) {
    check_image(path, image);
    if (!std::isfinite(exposure)) fail(path, "PNG preview exposure must be finite");
    AtomicTarget target(path);

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
    target.commit();
}

void write_text_atomic(const fs::path& path, const std::string& text) {
    AtomicTarget target(path);
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
    target.commit();
}

}  // namespace vpm
