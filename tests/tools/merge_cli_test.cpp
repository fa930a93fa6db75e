// `vpm merge`: pass sets rendered apart (render.first_pass) combine into the image of one run with
// all the passes; mismatched inputs are refused with one clear error and no output.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "render/run/image_io.h"

namespace fs = std::filesystem;

namespace {

int run_vpm(const std::string& args, const fs::path& dir, std::string* err = nullptr) {
    const fs::path e = dir / "stderr.txt";
    const int rc = WEXITSTATUS(std::system((std::string(VPM_BINARY) + " " + args + " 2> " + e.string() + " > /dev/null").c_str()));
    if (err) {
        std::ifstream in(e);
        std::stringstream s;
        s << in.rdbuf();
        *err = s.str();
    }
    return rc;
}

struct MergeCli : ::testing::Test {
    // One folder per test and process: ctest -j runs the tests of this fixture at the same time.
    fs::path dir = fs::temp_directory_path() /
                   ("vpm_merge_cli_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + "_" +
                    std::to_string(::getpid()));
    std::string render(const std::string& name, const std::string& sets) {
        const std::string out = (dir / name).string();
        EXPECT_EQ(run_vpm("render " + std::string(VPM_SOURCE_DIR) + "/configs/homogeneous.toml -q --set render.width=12 "
                          "--set render.height=10 --set render.integrator=photon_map --set photons.count=4000 " + sets +
                          " -o " + out, dir),
                  0);
        return out;
    }
    void SetUp() override {
        fs::remove_all(dir);
        fs::create_directories(dir);
    }
    void TearDown() override { fs::remove_all(dir); }
};

}  // namespace

TEST_F(MergeCli, SplitPassesMergeIntoTheSingleRun) {
    const std::string full = render("full.exr", "--set render.spp=6 --set render.passes=6");
    const std::string a = render("a.exr", "--set render.spp=2 --set render.passes=2");
    const std::string b = render("b.exr", "--set render.spp=4 --set render.passes=4 --set render.first_pass=2");
    ASSERT_EQ(run_vpm("merge " + b + " " + a + " -q -o " + (dir / "m.exr").string(), dir), 0);
    const vpm::Image m = vpm::read_exr(dir / "m.exr"), f = vpm::read_exr(full);
    ASSERT_EQ(m.rgb.size(), f.rgb.size());
    double worst = 0.0, peak = 0.0;
    for (size_t i = 0; i < m.rgb.size(); ++i) {
        worst = std::max(worst, std::abs(double(m.rgb[i]) - double(f.rgb[i])));
        peak = std::max(peak, std::abs(double(f.rgb[i])));
    }
    EXPECT_GT(peak, 0.0);
    EXPECT_LE(worst, 1e-6 * peak);   // float rounding of the stored pass means, nothing more
    EXPECT_TRUE(fs::exists(dir / "m.json"));
    EXPECT_TRUE(fs::exists(dir / "m.png"));
    // The merged record says what ran: the parts' integrator and gather, and their map estimates,
    // photons and samples summed, which are the single run's.
    auto sidecar = [](const fs::path& p) {
        std::ifstream in(p);
        return nlohmann::json::parse(in);
    };
    const nlohmann::json mj = sidecar(dir / "m.json"), fj = sidecar(dir / "full.json");
    EXPECT_EQ(mj["integrator_used"], "photon_map");
    EXPECT_EQ(mj["gather_used"], fj["gather_used"]);
    EXPECT_GT(mj["map_estimates"].get<uint64_t>(), 0u);
    EXPECT_EQ(mj["map_estimates"], fj["map_estimates"]);
    EXPECT_EQ(mj["photons"]["traced"]["pass_maps"], fj["photons"]["traced"]["pass_maps"]);
    EXPECT_EQ(mj["render"]["samples"], fj["render"]["samples"]);
    EXPECT_GT(mj["seconds"].get<double>(), 0.0);
    ASSERT_EQ(mj["merged_from"].size(), 2u);
    EXPECT_EQ(mj["merged_from"][0]["integrator_used"], "photon_map");
}

// Issue 24, item 8: `vpm render MERGED.json` renders the merged image (it rendered only the first
// input's passes: relative RMSE 0.146 against the merged image); with a gap between the pass ranges
// the sidecar says which passes its config renders.
TEST_F(MergeCli, MergedSidecarRendersTheMergedImage) {
    const std::string a = render("a.exr", "--set render.spp=2 --set render.passes=2");
    const std::string b = render("b.exr", "--set render.spp=4 --set render.passes=4 --set render.first_pass=2");
    ASSERT_EQ(run_vpm("merge " + b + " " + a + " -q -o " + (dir / "m.exr").string(), dir), 0);
    ASSERT_EQ(run_vpm("render " + (dir / "m.json").string() + " -q -o " + (dir / "again.exr").string(), dir), 0);
    const vpm::Image m = vpm::read_exr(dir / "m.exr"), again = vpm::read_exr(dir / "again.exr");
    ASSERT_EQ(m.rgb.size(), again.rgb.size());
    double worst = 0.0, peak = 0.0;
    for (size_t i = 0; i < m.rgb.size(); ++i) {
        worst = std::max(worst, std::abs(double(m.rgb[i]) - double(again.rgb[i])));
        peak = std::max(peak, std::abs(double(m.rgb[i])));
    }
    EXPECT_GT(peak, 0.0);
    EXPECT_LE(worst, 1e-6 * peak);
    std::ifstream in(dir / "m.json");
    std::stringstream text;
    text << in.rdbuf();
    EXPECT_NE(text.str().find("the merged image"), std::string::npos);
    // Passes 0..1 and 4..5: a gap, so the config is the first input's and the sidecar says so.
    const std::string c = render("c.exr", "--set render.spp=2 --set render.passes=2 --set render.first_pass=4");
    ASSERT_EQ(run_vpm("merge " + a + " " + c + " -q -o " + (dir / "g.exr").string(), dir), 0);
    std::ifstream gin(dir / "g.json");
    std::stringstream gtext;
    gtext << gin.rdbuf();
    EXPECT_NE(gtext.str().find("have gaps"), std::string::npos) << gtext.str();
}

TEST_F(MergeCli, RefusesOverlapOtherSettingsAndMissingSidecars) {
    const std::string a = render("a.exr", "--set render.spp=2 --set render.passes=2");
    const std::string c = render("c.exr", "--set render.spp=2 --set render.passes=2 --set render.first_pass=2 --set photons.k=9");
    const std::string d = render("d.exr", "--set render.spp=4 --set render.passes=2 --set render.first_pass=2");
    std::string err;
    EXPECT_EQ(run_vpm("merge " + a + " " + a + " -o " + (dir / "x.exr").string(), dir, &err), 1);
    EXPECT_NE(err.find("overlap"), std::string::npos) << err;
    EXPECT_EQ(run_vpm("merge " + a + " " + c + " -o " + (dir / "x.exr").string(), dir, &err), 1);
    EXPECT_NE(err.find("different scene or setting"), std::string::npos) << err;
    EXPECT_EQ(run_vpm("merge " + a + " " + d + " -o " + (dir / "x.exr").string(), dir, &err), 1);
    EXPECT_NE(err.find("samples per pass"), std::string::npos) << err;
    fs::remove(dir / "c.json");
    EXPECT_EQ(run_vpm("merge " + a + " " + c + " -o " + (dir / "x.exr").string(), dir, &err), 1);
    EXPECT_NE(err.find("c.json"), std::string::npos) << err;
    EXPECT_FALSE(fs::exists(dir / "x.exr"));
}

// Issue 24: a corrupt sidecar is one error naming the file and the key (exit 1), never an uncaught
// JSON exception (exit 3), an overflowed pass count or a negative image.
TEST_F(MergeCli, CorruptSidecarsAreOneErrorNamingTheKey) {
    const std::string a = render("a.exr", "--set render.spp=2 --set render.passes=2");
    const std::string b = render("b.exr", "--set render.spp=2 --set render.passes=2 --set render.first_pass=2");
    const fs::path json = dir / "b.json";
    std::ifstream in(json);
    const nlohmann::json good = nlohmann::json::parse(in);
    struct Case {
        const char* pointer;
        nlohmann::json value;
        const char* key;   // expected in the message
    };
    const std::vector<Case> cases = {
        {"/passes", 5, "passes"},
        {"/passes/count", "two", "passes.count"},
        {"/passes/count", 2147483648LL + 5, "passes.count"},
        {"/passes/count", 2.5, "passes.count"},
        {"/passes/count", 0, "passes.count"},
        {"/passes/first", nullptr, "passes.first"},
        {"/passes/first", -100, "passes.first"},
        {"/passes/first", 2147483647LL, "passes.first + passes.count"},
        {"/passes/first", 1e300, "passes.first"},
        {"/passes/spp_per_pass", "1", "passes.spp_per_pass"},
        {"/config", "x", "config"},
        {"/config/render", 3, "config.render"},
        {"/config/render/exposure", "bright", "config.render.exposure"},
        {"/config/render/exposure", 1e300, "config.render.exposure"},
    };
    for (const Case& c : cases) {
        nlohmann::json bad = good;
        bad[nlohmann::json::json_pointer(c.pointer)] = c.value;
        std::ofstream(json) << bad.dump();
        std::string err;
        EXPECT_EQ(run_vpm("merge " + a + " " + b + " -o " + (dir / "x.exr").string(), dir, &err), 1)
            << c.pointer << " = " << c.value.dump() << ": " << err;
        EXPECT_NE(err.find("b.json: " + std::string(c.key)), std::string::npos) << err;
        EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
        EXPECT_FALSE(fs::exists(dir / "x.exr"));
    }
    // A missing count (the key named) and an input that is no JSON object at all.
    nlohmann::json bad = good;
    bad["passes"].erase("count");
    std::ofstream(json) << bad.dump();
    std::string err;
    EXPECT_EQ(run_vpm("merge " + a + " " + b + " -o " + (dir / "x.exr").string(), dir, &err), 1);
    EXPECT_NE(err.find("passes.count is missing"), std::string::npos) << err;
    std::ofstream(json) << "[1, 2]";
    EXPECT_EQ(run_vpm("merge " + a + " " + b + " -o " + (dir / "x.exr").string(), dir, &err), 1);
    EXPECT_NE(err.find("not a vpm render sidecar"), std::string::npos) << err;
    // The repaired sidecar merges again: 4 passes.
    std::ofstream(json) << good.dump();
    ASSERT_EQ(run_vpm("merge " + a + " " + b + " -o " + (dir / "x.exr").string(), dir, &err), 0) << err;
    std::ifstream merged(dir / "x.json");
    EXPECT_EQ(nlohmann::json::parse(merged)["passes"]["count"].get<int>(), 4);
}

// Issue 24: NaN in an input survives the mean; merge warns about it as render does.
TEST_F(MergeCli, NonFiniteInputPixelsAreReported) {
    const std::string a = render("a.exr", "--set render.spp=2 --set render.passes=2");
    const std::string b = render("b.exr", "--set render.spp=2 --set render.passes=2 --set render.first_pass=2");
    vpm::Image image = vpm::read_exr(b);
    image.rgb[4] = std::nanf("");
    vpm::write_exr(b, image);
    std::string err;
    ASSERT_EQ(run_vpm("merge " + a + " " + b + " -o " + (dir / "x.exr").string(), dir, &err), 0) << err;
    EXPECT_NE(err.find("warning: 1 of 120 pixels are NaN or Inf"), std::string::npos) << err;
}
