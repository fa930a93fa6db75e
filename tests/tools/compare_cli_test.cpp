// `vpm compare IMAGE... REFERENCE`: several images against one reference, the repeat metrics over
// them with --repeats, and a warning for an image with more camera samples than its reference.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include <nlohmann/json.hpp>

#include "render/run/image_io.h"
#include "support/vpm_process.h"

using namespace vpm;
using namespace vpm::test;

namespace {

Image flat(float v) {
    Image im(8, 6);
    for (auto& x : im.rgb) x = v;
    return im;
}

}  // namespace

TEST(CompareCli, SeveralImagesAndTheirRepeatMetricsAgainstOneReference) {
    ScratchDir dir;
    write_exr(dir.path / "ref.exr", flat(0.5f));
    write_exr(dir.path / "a.exr", flat(0.55f));   // +10 %
    write_exr(dir.path / "b.exr", flat(0.45f));   // -10 %
    Outcome o = run_vpm("compare " + quote(dir.path / "a.exr") + " " + quote(dir.path / "b.exr") + " " +
                            quote(dir.path / "ref.exr") + " --repeats --json",
                        dir.path);
    ASSERT_EQ(o.code, 0) << o.err;
    const nlohmann::json j = nlohmann::json::parse(o.out);
    ASSERT_EQ(j["images"].size(), 2u);
    EXPECT_NEAR(j["images"][0]["luminance_rel_bias"].get<double>(), 0.1, 1e-6);
    EXPECT_NEAR(j["images"][1]["luminance_rel_bias"].get<double>(), -0.1, 1e-6);
    // Per-repeat biases +0.1 and -0.1: mean 0, standard error std / sqrt(2) = 0.1; per pixel the
    // two repeats are the mean +- 0.1, so the variance is 0.02 and the MSE 0.01.
    const nlohmann::json& r = j["repeats"];
    EXPECT_EQ(r["repeats"], 2);
    EXPECT_NEAR(r["rel_bias"].get<double>(), 0.0, 1e-6);
    EXPECT_NEAR(r["rel_bias_se"].get<double>(), 0.1, 1e-6);
    EXPECT_NEAR(r["rel_variance"].get<double>(), 0.02, 1e-6);
    EXPECT_NEAR(r["rel_mse"].get<double>(), 0.01, 1e-6);
    EXPECT_TRUE(o.err.empty()) << o.err;   // no sidecars: no samples to compare, no warning

    // Text: one line per image and the repeat line.
    o = run_vpm("compare " + quote(dir.path / "a.exr") + " " + quote(dir.path / "b.exr") + " " +
                    quote(dir.path / "ref.exr") + " --repeats",
                dir.path);
    ASSERT_EQ(o.code, 0) << o.err;
    EXPECT_NE(o.out.find("a.exr vs "), std::string::npos) << o.out;
    EXPECT_NE(o.out.find("b.exr vs "), std::string::npos) << o.out;
    EXPECT_NE(o.out.find("2 repeats"), std::string::npos) << o.out;
    // --repeats needs two images; one image alone is the two-argument form of before.
    o = run_vpm("compare " + quote(dir.path / "a.exr") + " " + quote(dir.path / "ref.exr") + " --repeats", dir.path);
    EXPECT_EQ(o.code, 2) << o.err;
    EXPECT_NE(o.err.find("--repeats"), std::string::npos) << o.err;
    o = run_vpm("compare " + quote(dir.path / "a.exr") + " " + quote(dir.path / "ref.exr") + " --json", dir.path);
    ASSERT_EQ(o.code, 0) << o.err;
    EXPECT_NEAR(nlohmann::json::parse(o.out)["relative_bias"].get<double>(), 0.1, 1e-6);
}

TEST(CompareCli, WarnsWhenAnImageHasMoreSamplesThanItsReference) {
    ScratchDir dir;
    write_exr(dir.path / "ref.exr", flat(0.5f));
    write_exr(dir.path / "a.exr", flat(0.5f));
    write_exr(dir.path / "b.exr", flat(0.5f));
    write_file(dir.path / "ref.json", R"({"render": {"samples": 480}})");
    write_file(dir.path / "a.json", R"({"render": {"samples": 960}})");
    write_file(dir.path / "b.json", R"({"render": {"samples": 480}})");
    const Outcome o = run_vpm("compare " + quote(dir.path / "a.exr") + " " + quote(dir.path / "b.exr") + " " +
                                  quote(dir.path / "ref.exr"),
                              dir.path);
    ASSERT_EQ(o.code, 0) << o.err;
    EXPECT_TRUE(o.one_line()) << o.err;   // a.exr only: b.exr has as many samples as the reference
    EXPECT_NE(o.err.find("a.exr took 960 camera samples, more than the 480 of its reference"), std::string::npos) << o.err;
}

// The named metric: relMSE by default and named in the report; --metric, --exclude and --crop choose
// what is measured; a variance image beside the reference (or two halves) gives the noise floor that
// is subtracted.
TEST(CompareCli, NamedMetricMaskAndReferenceNoise) {
    ScratchDir dir;
    Image ref = flat(0.5f), img = flat(0.55f);
    ref.set(0, 0, Rgb(100, 100, 100));   // a glint the image gets half right
    img.set(0, 0, Rgb(50, 50, 50));
    write_exr(dir.path / "ref.exr", ref);
    write_exr(dir.path / "img.exr", img);
    const std::string files = quote(dir.path / "img.exr") + " " + quote(dir.path / "ref.exr");
    Outcome o = run_vpm("compare --json " + files, dir.path);
    ASSERT_EQ(o.code, 0) << o.err;
    nlohmann::json j = nlohmann::json::parse(o.out);
    EXPECT_EQ(j["metric"], "relMSE");
    const double per_pixel = 0.0025 / 0.26;   // (0.05)^2 / (0.5^2 + 0.01)
    EXPECT_NEAR(j["error"].get<double>(), (47 * per_pixel + 2500.0 / 10000.01) / 48, 1e-6);
    EXPECT_TRUE(j["noise_floor"].is_null());
    // relRMSE without the glint: 0.05 / 0.5.
    o = run_vpm("compare --json --metric relrmse --exclude 0,0,1,1 " + files, dir.path);
    ASSERT_EQ(o.code, 0) << o.err;
    j = nlohmann::json::parse(o.out);
    EXPECT_EQ(j["metric"], "relRMSE");
    EXPECT_NEAR(j["error"].get<double>(), 0.1, 1e-6);
    EXPECT_EQ(j["pixels"], 47);
    o = run_vpm("compare --json --metric smape --crop 1,0,8,6 " + files, dir.path);
    ASSERT_EQ(o.code, 0) << o.err;
    EXPECT_NEAR(nlohmann::json::parse(o.out)["error"].get<double>(), 0.05 / 1.06, 1e-6);
    // A variance image beside the reference: its floor is subtracted and the report says from where.
    Image var(8, 6);
    for (auto& x : var.rgb) x = 0.0013f;
    write_exr(dir.path / "ref.variance.exr", var);
    o = run_vpm("compare --exclude 0,0,1,1 " + files, dir.path);
    ASSERT_EQ(o.code, 0) << o.err;
    EXPECT_NE(o.out.find("metric: relMSE = mean (I - R)^2 / (R^2 + 0.01) over luminance"), std::string::npos) << o.out;
    EXPECT_NE(o.out.find("reference noise from " + (dir.path / "ref.variance.exr").string()), std::string::npos) << o.out;
    o = run_vpm("compare --json --exclude 0,0,1,1 " + files, dir.path);
    j = nlohmann::json::parse(o.out);
    EXPECT_NEAR(j["noise_floor"].get<double>(), 0.0013 / 0.26, 1e-6);
    EXPECT_NEAR(j["error"].get<double>(), per_pixel - 0.0013 / 0.26, 1e-6);
    // Two halves: the reference is their mean, the floor ((A - B) / 2)^2 / (R^2 + eps).
    write_exr(dir.path / "a.exr", flat(0.4f));
    write_exr(dir.path / "b.exr", flat(0.6f));
    o = run_vpm("compare --json --reference-halves " + quote(dir.path / "a.exr") + " " + quote(dir.path / "b.exr") + " " +
                    quote(dir.path / "img.exr") + " --crop 1,0,8,6",
                dir.path);
    ASSERT_EQ(o.code, 0) << o.err;
    j = nlohmann::json::parse(o.out);
    EXPECT_NEAR(j["noise_floor"].get<double>(), 0.01 / 0.26, 1e-6);
    // Bad metric and rectangles: usage errors naming the option.
    o = run_vpm("compare --metric psnr " + files, dir.path);
    EXPECT_EQ(o.code, 2);
    EXPECT_NE(o.err.find("--metric"), std::string::npos) << o.err;
    o = run_vpm("compare --crop 3,3,1,1 " + files, dir.path);
    EXPECT_NE(o.code, 0);
    EXPECT_NE(o.err.find("--crop"), std::string::npos) << o.err;
}

// vpm render --variance writes OUT.variance.exr from the passes' spread; vpm compare then uses it
// against that render as a reference; a later render to the same OUT without it removes it.
TEST(CompareCli, RenderWritesAVarianceImageThatCompareUses) {
    ScratchDir dir;
    const std::string config = quote(std::string(VPM_SOURCE_DIR) + "/configs/homogeneous.toml");
    const std::string small = " --set render.width=16 --set render.height=12 --set render.spp=4 -q";
    Outcome o = run_vpm("render " + config + small + " --set render.passes=4 --variance -o " + quote(dir.path / "ref.exr"), dir.path);
    ASSERT_EQ(o.code, 0) << o.err;
    ASSERT_TRUE(fs::exists(dir.path / "ref.variance.exr"));
    const Image v = read_exr(dir.path / "ref.variance.exr");
    EXPECT_EQ(v.width, 16);
    double sum = 0;
    for (float x : v.rgb) sum += x;
    EXPECT_GT(sum, 0.0);
    o = run_vpm("render " + config + small + " --set render.seed=9 -o " + quote(dir.path / "img.exr"), dir.path);
    ASSERT_EQ(o.code, 0) << o.err;
    o = run_vpm("compare --json " + quote(dir.path / "img.exr") + " " + quote(dir.path / "ref.exr"), dir.path);
    ASSERT_EQ(o.code, 0) << o.err;
    const nlohmann::json j = nlohmann::json::parse(o.out);
    EXPECT_GT(j["noise_floor"].get<double>(), 0.0);
    EXPECT_NEAR(j["error"].get<double>(), j["error_raw"].get<double>() - j["noise_floor"].get<double>(), 1e-9);
    // --variance with one pass and no time limit: refused before the work.
    o = run_vpm("render " + config + small + " --variance -o " + quote(dir.path / "one.exr"), dir.path);
    EXPECT_EQ(o.code, 1);
    EXPECT_NE(o.err.find("--variance: needs two or more passes"), std::string::npos) << o.err;
    EXPECT_FALSE(fs::exists(dir.path / "one.exr"));
    // Rendering ref.exr again without --variance: the old variance no longer describes it.
    o = run_vpm("render " + config + small + " -o " + quote(dir.path / "ref.exr"), dir.path);
    ASSERT_EQ(o.code, 0) << o.err;
    EXPECT_FALSE(fs::exists(dir.path / "ref.variance.exr"));
}

// --exclude-lights CONFIG leaves out the pixels where the config's scene shows an area light
// (configs/glass_sphere_fog.toml: its light's glint through the glass ball); a missing file is a usage
// error, an unreadable config or images of another aspect ratio one clear error naming it.
TEST(CompareCli, ExcludeLightsLeavesOutTheSeenLightAndNamesABadConfig) {
    ScratchDir dir;
    Image ref(64, 64), img(64, 64);
    for (auto& x : ref.rgb) x = 0.5f;
    for (auto& x : img.rgb) x = 0.5f;
    write_exr(dir.path / "ref.exr", ref);
    write_exr(dir.path / "img.exr", img);
    const std::string files = quote(dir.path / "img.exr") + " " + quote(dir.path / "ref.exr");
    const std::string glass = quote(std::string(VPM_SOURCE_DIR) + "/configs/glass_sphere_fog.toml");
    Outcome o = run_vpm("compare --json --exclude-lights " + glass + " " + files, dir.path);
    ASSERT_EQ(o.code, 0) << o.err;
    const int pixels = nlohmann::json::parse(o.out)["pixels"].get<int>();
    EXPECT_LT(pixels, 64 * 64);
    EXPECT_GT(pixels, 64 * 64 / 2);

    o = run_vpm("compare --exclude-lights " + quote(dir.path / "missing.toml") + " " + files, dir.path);
    EXPECT_EQ(o.code, 2);
    EXPECT_NE(o.err.find("--exclude-lights"), std::string::npos) << o.err;

    std::ofstream(dir.path / "bad.toml") << "[camera\n";
    o = run_vpm("compare --exclude-lights " + quote(dir.path / "bad.toml") + " " + files, dir.path);
    EXPECT_EQ(o.code, 1);
    EXPECT_NE(o.err.find("bad.toml"), std::string::npos) << o.err;

    write_exr(dir.path / "wide.exr", flat(0.5f));
    write_exr(dir.path / "wide_ref.exr", flat(0.5f));
    o = run_vpm("compare --exclude-lights " + glass + " " + quote(dir.path / "wide.exr") + " " +
                    quote(dir.path / "wide_ref.exr"),
                dir.path);
    EXPECT_EQ(o.code, 1);
    EXPECT_NE(o.err.find("aspect"), std::string::npos) << o.err;
}
