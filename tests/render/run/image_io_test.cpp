#include "render/run/image_io.h"

#include <png.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <thread>

#include "core/error.h"
#include "support/io_test_util.h"

namespace {

using namespace vpm;
using vpm_test::TempDirTest;
namespace fs = std::filesystem;

class ImageIo : public TempDirTest {};

Image test_image(int w, int h) {
    Image img(w, h);
    const float specials[] = {0.0f, -0.0f, 1.0f, 1.0f / 3.0f, -123.456f,
                              std::numeric_limits<float>::min(),          // smallest normal
                              std::numeric_limits<float>::denorm_min(),   // tiny subnormal
                              std::numeric_limits<float>::max(),          // huge
                              1e-30f, 6.02e23f, 65504.0f, 65505.0f /* not a half */};
    const size_t n = sizeof(specials) / sizeof(specials[0]);
    for (size_t i = 0; i < img.rgb.size(); ++i)
        img.rgb[i] = i < n ? specials[i] : float(std::sin(double(i)) * std::pow(10.0, double(i % 17) - 8.0));
    return img;
}

void expect_message_names(const FileError& e, const fs::path& p) {
    EXPECT_NE(std::string(e.what()).find(p.string()), std::string::npos) << e.what();
}

TEST_F(ImageIo, ExrRoundTripIsBitExact) {
    const Image img = test_image(13, 7);
    const fs::path p = dir_ / "round.exr";
    write_exr(p, img);
    const Image back = read_exr(p);
    ASSERT_EQ(back.width, 13);
    ASSERT_EQ(back.height, 7);
    ASSERT_EQ(back.rgb.size(), img.rgb.size());
    EXPECT_EQ(std::memcmp(back.rgb.data(), img.rgb.data(), img.rgb.size() * sizeof(float)), 0);
    EXPECT_EQ(back.at(3, 0)[0], img.at(3, 0)[0]);
    EXPECT_EQ(entries(dir_), std::vector<std::string>{"round.exr"});   // no temp left
}

TEST_F(ImageIo, ExrOverwriteReplacesOldFile) {
    const fs::path p = dir_ / "a.exr";
    write_exr(p, Image(2, 2));
    Image img(3, 1);
    img.set(2, 0, Rgb(1, 2, 3));
    write_exr(p, img);
    const Image back = read_exr(p);
    EXPECT_EQ(back.width, 3);
    EXPECT_EQ(back.at(2, 0)[2], 3.0);
}

TEST_F(ImageIo, WriteIntoMissingFolderThrowsAndLeavesNothing) {
    const fs::path p = dir_ / "no_such_folder" / "out.exr";
    try {
        write_exr(p, Image(2, 2));
        FAIL() << "expected FileError";
    } catch (const FileError& e) {
        expect_message_names(e, p);
        EXPECT_NE(std::string(e.what()).find("does not exist"), std::string::npos) << e.what();
    }
    EXPECT_TRUE(entries(dir_).empty());
    EXPECT_THROW(write_png_preview(p, Image(2, 2)), FileError);
    EXPECT_THROW(write_text_atomic(p, "x"), FileError);
    EXPECT_TRUE(entries(dir_).empty());
}

TEST_F(ImageIo, WriteBelowARegularFileThrows) {
    // Tests run as root, so permissions cannot make a folder unwritable; a parent that is a
    // regular file fails for everyone.
    const fs::path file = dir_ / "plain.txt";
    write_text_atomic(file, "hello");
    const fs::path p = file / "out.exr";
    try {
        write_exr(p, Image(2, 2));
        FAIL() << "expected FileError";
    } catch (const FileError& e) {
        expect_message_names(e, p);
    }
    EXPECT_THROW(write_png_preview(p, Image(2, 2)), FileError);
    EXPECT_THROW(write_text_atomic(p, "x"), FileError);
    EXPECT_EQ(entries(dir_), std::vector<std::string>{"plain.txt"});
    EXPECT_EQ(slurp(file), "hello");
}

TEST_F(ImageIo, FailedWriteLeavesExistingFileUnchanged) {
    const fs::path p = dir_ / "keep.exr";
    write_exr(p, test_image(4, 4));
    const std::string before = slurp(p);

    Image bad(4, 4);
    bad.rgb.resize(5);   // inconsistent: the writer must refuse before touching anything
    EXPECT_THROW(write_exr(p, bad), FileError);
    EXPECT_THROW(write_png_preview(p, bad), FileError);
    EXPECT_THROW(write_exr(p, Image()), FileError);
    EXPECT_EQ(slurp(p), before);
    EXPECT_EQ(entries(dir_), std::vector<std::string>{"keep.exr"});
}

TEST_F(ImageIo, TargetThatIsAFolderIsRefusedAndKept) {
    const fs::path p = dir_ / "out.exr";
    fs::create_directory(p);
    fs::create_directory(p / "inside");
    try {
        write_exr(p, Image(2, 2));
        FAIL() << "expected FileError";
    } catch (const FileError& e) {
        expect_message_names(e, p);
    }
    EXPECT_THROW(write_text_atomic(p, "x"), FileError);
    EXPECT_TRUE(fs::is_directory(p / "inside"));
    EXPECT_EQ(entries(dir_), std::vector<std::string>{"out.exr"});
}

TEST_F(ImageIo, ReadErrorsNameTheFile) {
    const fs::path missing = dir_ / "missing.exr";
    try {
        read_exr(missing);
        FAIL() << "expected FileError";
    } catch (const FileError& e) {
        expect_message_names(e, missing);
    }
    const fs::path text = dir_ / "not.exr";
    write_text_atomic(text, "this is not an OpenEXR file\n");
    try {
        read_exr(text);
        FAIL() << "expected FileError";
    } catch (const FileError& e) {
        expect_message_names(e, text);
        EXPECT_NE(std::string(e.what()).find("not an OpenEXR"), std::string::npos) << e.what();
    }
    // A truncated EXR: valid magic number, broken body.
    const fs::path good = dir_ / "good.exr";
    write_exr(good, test_image(64, 64));
    const std::string bytes = slurp(good);
    const fs::path cut = dir_ / "cut.exr";
    write_text_atomic(cut, bytes.substr(0, bytes.size() / 2));
    try {
        read_exr(cut);
        FAIL() << "expected FileError";
    } catch (const FileError& e) {
        expect_message_names(e, cut);
    }
    EXPECT_THROW(read_exr(dir_), FileError);
}

struct Png {
    int width = 0, height = 0;
    std::vector<unsigned char> rgb;
    bool srgb_flag = false;
};

Png read_png(const fs::path& p) {
    png_image img;
    std::memset(&img, 0, sizeof(img));
    img.version = PNG_IMAGE_VERSION;
    Png out;
    if (!png_image_begin_read_from_file(&img, p.c_str())) {
        ADD_FAILURE() << "libpng cannot read " << p << ": " << img.message;
        return out;
    }
    img.format = PNG_FORMAT_RGB;
    out.width = int(img.width);
    out.height = int(img.height);
    out.rgb.resize(PNG_IMAGE_SIZE(img));
    if (!png_image_finish_read(&img, nullptr, out.rgb.data(), 0, nullptr))
        ADD_FAILURE() << "libpng cannot decode " << p << ": " << img.message;
    png_image_free(&img);
    return out;
}

TEST_F(ImageIo, PngPreviewHasSrgbValues) {
    Image img(5, 3);
    img.set(0, 0, Rgb(0.5, 0.0, 1.0));      // 0.5 linear -> 0.7354 sRGB -> 188
    img.set(1, 0, Rgb(0.002, 2.0, -1.0));   // linear segment: 12.92 * 0.002 * 255 = 6.6 -> 7
    img.set(2, 0, Rgb(std::nan(""), 0.5, 0.5));   // NaN pixel -> magenta
    img.set(4, 2, Rgb(0.2158605, 0.2158605, 0.2158605));   // sRGB 128/255 -> 128
    const fs::path p = dir_ / "preview.png";
    write_png_preview(p, img);
    const Png png = read_png(p);
    ASSERT_EQ(png.width, 5);
    ASSERT_EQ(png.height, 3);
    ASSERT_EQ(png.rgb.size(), size_t(5 * 3 * 3));
    auto px = [&](int x, int y, int c) { return int(png.rgb[size_t(3 * (y * 5 + x) + c)]); };
    EXPECT_EQ(px(0, 0, 0), 188);
    EXPECT_EQ(px(0, 0, 1), 0);
    EXPECT_EQ(px(0, 0, 2), 255);
    EXPECT_EQ(px(1, 0, 0), 7);
    EXPECT_EQ(px(1, 0, 1), 255);   // clamped for display only
    EXPECT_EQ(px(1, 0, 2), 0);
    EXPECT_EQ(px(2, 0, 0), 255);
    EXPECT_EQ(px(2, 0, 1), 0);
    EXPECT_EQ(px(2, 0, 2), 255);
    EXPECT_EQ(px(4, 2, 1), 128);
    EXPECT_EQ(px(3, 1, 0), 0);
    EXPECT_EQ(entries(dir_), std::vector<std::string>{"preview.png"});
}

TEST_F(ImageIo, PngExposureIsPowerOfTwo) {
    Image img(1, 1);
    img.set(0, 0, Rgb(0.25, 0.125, 1.0));
    const fs::path p = dir_ / "exp.png";
    write_png_preview(p, img, 1.0);   // x2: 0.5, 0.25, 2 -> 188, 137, 255
    const Png png = read_png(p);
    ASSERT_EQ(png.rgb.size(), 3u);
    EXPECT_EQ(int(png.rgb[0]), 188);
    EXPECT_EQ(int(png.rgb[1]), 137);
    EXPECT_EQ(int(png.rgb[2]), 255);
    write_png_preview(p, img, -2.0);   // /4: 1.0 -> 0.25 -> 137
    EXPECT_EQ(int(read_png(p).rgb[2]), 137);
}

TEST_F(ImageIo, WriteTextAtomic) {
    const fs::path p = dir_ / "table.csv";
    write_text_atomic(p, "a,b\n1,2\n");
    EXPECT_EQ(slurp(p), "a,b\n1,2\n");
    write_text_atomic(p, "");
    EXPECT_EQ(slurp(p), "");
    std::string big(3 << 20, 'x');
    big[12345] = '\0';
    write_text_atomic(p, big);
    EXPECT_EQ(slurp(p), big);
    EXPECT_EQ(entries(dir_), std::vector<std::string>{"table.csv"});
}

TEST_F(ImageIo, ConcurrentWritersNeverCollide) {
    const fs::path p = dir_ / "shared.txt";
    const fs::path q = dir_ / "shared.exr";
    std::vector<std::thread> threads;
    std::atomic<int> failures{0};
    for (int t = 0; t < 6; ++t) {
        threads.emplace_back([&, t] {
            for (int i = 0; i < 30; ++i) {
                try {
                    write_text_atomic(p, "thread " + std::to_string(t) + "\n");
                    if (i % 10 == 0) write_exr(q, Image(8, 8));
                } catch (...) {
                    ++failures;
                }
            }
        });
    }
    for (auto& th : threads) th.join();
    EXPECT_EQ(failures.load(), 0);
    const std::string text = slurp(p);
    EXPECT_EQ(text.rfind("thread ", 0), 0u);
    EXPECT_EQ(read_exr(q).width, 8);
    EXPECT_EQ(entries(dir_), (std::vector<std::string>{"shared.exr", "shared.txt"}));
}

}  // namespace
