// `vpm render` as a user runs it: outputs, sidecar contents, the build log, and determinism
// across thread counts.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "render/run/image_io.h"
#include "support/scratch_dir.h"

namespace fs = std::filesystem;

namespace {


// Runs the vpm binary; returns the exit code, stderr in `err`.
int run_vpm(const std::string& args, const fs::path& dir, std::string& err) {
    const fs::path err_file = dir / "stderr.txt";
    const std::string cmd = std::string(VPM_BINARY) + " " + args + " 2> " + err_file.string() + " > /dev/null";
    const int status = std::system(cmd.c_str());
    std::ifstream in(err_file);
    std::stringstream s;
    s << in.rdbuf();
    err = s.str();
    return WEXITSTATUS(status);
}

nlohmann::json read_json(const fs::path& p) {
    std::ifstream in(p);
    return nlohmann::json::parse(in);
}

const std::string kConfig = std::string(VPM_SOURCE_DIR) + "/configs/homogeneous.toml";
const std::string kSmall = " --set render.width=24 --set render.height=16 --set render.spp=4";

}  // namespace

TEST(RenderCli, WritesExrPngAndSidecarWithPhaseTimings) {
    const vpm::test::ScratchDir t;
    std::string err;
    const fs::path out = t.path / "img.exr";
    ASSERT_EQ(run_vpm("render " + kConfig + kSmall + " -o " + out.string(), t.path, err), 0) << err;
    EXPECT_TRUE(fs::exists(out));
    EXPECT_TRUE(fs::exists(t.path / "img.png"));
    const auto j = read_json(t.path / "img.json");
    for (const char* phase : {"load", "render", "write"}) {
        ASSERT_TRUE(j["phases"].contains(phase)) << phase;
        EXPECT_GE(j["phases"][phase]["seconds"].get<double>(), 0.0);
        EXPECT_GT(j["phases"][phase]["peak_rss_bytes"].get<double>(), 0.0);
    }
    EXPECT_EQ(j["config"]["render"]["width"], 24);
    EXPECT_EQ(j["config"]["render"]["output"], out.string());
    EXPECT_EQ(j["render"]["nonfinite_samples"], 0);
    EXPECT_GT(j["render"]["samples_per_second"].get<double>(), 0.0);
    EXPECT_TRUE(j.contains("git_revision"));
    EXPECT_TRUE(j.contains("seed"));
    // The run log says what was built: a homogeneous scene builds neither Embree nor OpenVDB.
    EXPECT_NE(err.find("Embree: not built (no shapes)"), std::string::npos) << err;
    EXPECT_NE(err.find("OpenVDB: not used (no grid media)"), std::string::npos) << err;
    const vpm::Image image = vpm::read_exr(out);
    EXPECT_EQ(image.width, 24);
    EXPECT_EQ(image.height, 16);
}

TEST(RenderCli, SameImageForOneAndTwoThreads) {
    const vpm::test::ScratchDir t;
    std::string err;
    for (const char* threads : {"1", "2"}) {
        const std::string out = (t.path / (std::string("t") + threads + ".exr")).string();
        ASSERT_EQ(run_vpm("render " + kConfig + kSmall + " --set render.integrator=photon_map --set photons.count=20000 "
                          "--threads " + threads + " -q -o " + out, t.path, err), 0) << err;
    }
    const vpm::Image a = vpm::read_exr(t.path / "t1.exr"), b = vpm::read_exr(t.path / "t2.exr");
    ASSERT_EQ(a.rgb.size(), b.rgb.size());
    EXPECT_EQ(a.rgb, b.rgb);
    EXPECT_EQ(read_json(t.path / "t2.json")["threads"], 2);
}

TEST(RenderCli, PhotonMapRunRecordsItsPhasesAndEnergy) {
    const vpm::test::ScratchDir t;
    std::string err;
    const fs::path out = t.path / "pm.exr";
    ASSERT_EQ(run_vpm("render " + kConfig + kSmall + " --set render.integrator=photon_map --set photons.count=20000 -o " +
                      out.string(), t.path, err), 0) << err;
    const auto j = read_json(t.path / "pm.json");
    for (const char* phase : {"trace", "build", "render"}) EXPECT_TRUE(j["phases"].contains(phase)) << phase;
    EXPECT_GT(j["photons"]["stored"].get<double>(), 0.0);
    EXPECT_LE(j["photons"]["bytes_per_photon"].get<double>(), 32.0);
    EXPECT_LT(j["photons"]["energy"]["relative_imbalance"].get<double>(), 1e-6);
    EXPECT_NE(err.find("trace: 20000 photon paths"), std::string::npos) << err;
}

TEST(RenderCli, PathTracerRunsNoPhotonPass) {
    const vpm::test::ScratchDir t;
    std::string err;
    ASSERT_EQ(run_vpm("render " + kConfig + kSmall + " -o " + (t.path / "pt.exr").string(), t.path, err), 0) << err;
    EXPECT_FALSE(read_json(t.path / "pt.json")["phases"].contains("trace"));
    EXPECT_EQ(err.find("trace:"), std::string::npos) << err;
}

TEST(RenderCli, BadConfigFailsWithOneLineAndNoOutput) {
    const vpm::test::ScratchDir t;
    std::string err;
    const fs::path out = t.path / "bad.exr";
    EXPECT_EQ(run_vpm("render " + kConfig + " --set media.0.g=1.5 -o " + out.string(), t.path, err), 1);
    EXPECT_NE(err.find("media.0.g: value 1.5 is out of range; allowed: (-1, 1)"), std::string::npos) << err;
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
    EXPECT_FALSE(fs::exists(out));
    EXPECT_FALSE(fs::exists(t.path / "bad.json"));
}

TEST(RenderCli, HelpOnEverySubcommand) {
    const vpm::test::ScratchDir t;
    std::string err;
    for (const char* cmd : {"render", "study", "make-media", "make-sky"})
        EXPECT_EQ(run_vpm(std::string(cmd) + " --help", t.path, err), 0) << cmd << ": " << err;
    EXPECT_EQ(run_vpm("--help", t.path, err), 0);
    EXPECT_EQ(run_vpm("nonsense", t.path, err), 2);
}

TEST(RenderCli, PhotonMapWithoutMediaBuildsNoVolumeMap) {
    const vpm::test::ScratchDir t;
    std::ofstream(t.path / "walls.toml") << R"(
[render]
width = 16
height = 16
spp = 2
integrator = "photon_map"
[camera]
position = [0, 1, 4]
look_at = [0, 0, 0]
[[lights]]
type = "point"
position = [0, 2, 0]
intensity = 5
[[shapes]]
type = "quad"
center = [0, 0, 0]
u = [2, 0, 0]
v = [0, 0, -2]
)";
    std::string err;
    ASSERT_EQ(run_vpm("render " + (t.path / "walls.toml").string() + " -o " + (t.path / "w.exr").string(), t.path, err), 0)
        << err;
    // The photon pass runs for the surface map; the volume map stays empty.
    EXPECT_NE(err.find("no media, so the volume photon map is empty"), std::string::npos) << err;
    EXPECT_EQ(read_json(t.path / "w.json")["photons"]["stored"], 0);
    // With final gather there is no surface map either, so no photon pass at all.
    ASSERT_EQ(run_vpm("render " + (t.path / "walls.toml").string() + " --set photons.final_gather=true -o " +
                      (t.path / "g.exr").string(), t.path, err), 0) << err;
    EXPECT_NE(err.find("no media and no surface map, so no photon pass"), std::string::npos) << err;
    EXPECT_FALSE(read_json(t.path / "g.json")["phases"].contains("trace"));
}

// Issue 24: photons.k above the stored count on the homogeneous sphere ran for minutes (each march
// point gathered the whole map). Now a warning names k and the stored count, the map is never
// queried and camera paths continue instead: a run of well under a second.
TEST(RenderCli, KAboveTheStoredCountWarnsAndIsBounded) {
    const vpm::test::ScratchDir dir;
    std::string err;
    const int rc = run_vpm("render " + std::string(VPM_SOURCE_DIR) + "/configs/homogeneous.toml --threads 1 "
                           "--set render.width=16 --set render.height=16 --set render.spp=4 "
                           "--set render.integrator=photon_map --set photons.count=20000 --set photons.k=65536 -o " +
                               (dir.path / "k.exr").string(),
                           dir.path, err);
    ASSERT_EQ(rc, 0) << err;
    EXPECT_NE(err.find("warning: photons.k = 65536 exceeds the "), std::string::npos) << err;
    std::ifstream in(dir.path / "k.json");
    const auto j = nlohmann::json::parse(in);
    EXPECT_EQ(j["photons"]["estimate_cases"]["queries"].get<uint64_t>(), 0u);
    EXPECT_LT(j["photons"]["stored"].get<uint64_t>(), 65536u);
    // The record says so as well (a run under -q has no log).
    EXPECT_NE(j["warnings"].dump().find("photons.k = 65536 exceeds the "), std::string::npos) << j.dump();
    // The paths go on past the map, continued one by one (the photon map never drops its map).
    const uint64_t continued = j["photons"]["continued_paths"].get<uint64_t>() +
                               j["photons"].value("march_wide_queries", uint64_t(0));
    EXPECT_GT(continued, 0u) << j["photons"].dump();
    EXPECT_EQ(j["integrator_used"], "photon_map");
    EXPECT_EQ(j["map_estimates"].get<uint64_t>(), 0u);
}

// Issue 24: a light of zero power (here a black sky) was blamed on reachability ("none of its light
// can reach the scene's media or shapes"); the warning now says its power is zero and why it can be.
TEST(RenderCli, ZeroPowerLightIsNotBlamedOnReachability) {
    const vpm::test::ScratchDir dir;
    std::ofstream(dir.path / "dark.toml") << "[render]\nwidth = 4\nheight = 4\nspp = 1\nintegrator = \"photon_map\"\n"
                                             "[photons]\ncount = 2000\n"
                                             "[[lights]]\ntype = \"environment\"\nradiance = 0\n"
                                             "[[lights]]\ntype = \"point\"\nposition = [0, 0, 0]\nintensity = 1\n"
                                             "[[media]]\ntype = \"homogeneous\"\nshape = \"sphere\"\nradius = 1\n";
    std::string err;
    ASSERT_EQ(run_vpm("render " + (dir.path / "dark.toml").string() + " -o " + (dir.path / "d.exr").string(), dir.path, err), 0)
        << err;
    EXPECT_NE(err.find("warning: light 0 (constant environment"), std::string::npos) << err;
    EXPECT_NE(err.find("its power towards the scene's media and shapes is zero (it emits nothing, or"), std::string::npos) << err;
    EXPECT_EQ(err.find("none of its light can reach the scene's media or shapes;"), std::string::npos) << err;
}
