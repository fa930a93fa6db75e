// `vpm compare IMAGE... REFERENCE`: several images against one reference, the repeat metrics over
// them with --repeats, and a warning for an image with more camera samples than its reference.
#include <gtest/gtest.h>

#include <cmath>

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
