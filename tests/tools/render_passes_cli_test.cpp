// `vpm render --reference REF.exr` with passes: the error of the mean so far after every pass, in
// OUT.passes.csv and the sidecar.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include <nlohmann/json.hpp>

#include "render/run/image_io.h"
#include "support/scratch_dir.h"

namespace fs = std::filesystem;

namespace {

int run_vpm(const std::string& args, const fs::path& dir) {
    const std::string cmd = std::string(VPM_BINARY) + " " + args + " 2> " + (dir / "stderr.txt").string() + " > /dev/null";
    return WEXITSTATUS(std::system(cmd.c_str()));
}

std::string read_text(const fs::path& p) {
    std::ifstream in(p);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

std::vector<std::vector<std::string>> read_csv(const fs::path& p) {
    std::ifstream in(p);
    std::vector<std::vector<std::string>> rows;
    for (std::string line; std::getline(in, line);) {
        std::vector<std::string> row;
        std::stringstream s(line);
        for (std::string cell; std::getline(s, cell, ',');) row.push_back(cell);
        rows.push_back(row);
    }
    return rows;
}

}  // namespace

TEST(RenderPassesCli, ReferenceErrorAfterEveryPass) {
    const vpm::test::ScratchDir scratch;
    const fs::path& dir = scratch.path;
    const std::string config = std::string(VPM_SOURCE_DIR) + "/configs/homogeneous.toml";
    const std::string small = " -q --set render.width=16 --set render.height=16 ";
    ASSERT_EQ(run_vpm("render " + config + small + "--set render.spp=64 -o " + (dir / "ref.exr").string(), dir), 0);
    ASSERT_EQ(run_vpm("render " + config + small +
                          "--set render.integrator=photon_map --set photons.count=5000 --set photons.gather=collision --set render.spp=8 "
                          "--set render.passes=8 --reference " + (dir / "ref.exr").string() + " -o " +
                          (dir / "pm.exr").string(),
                      dir),
              0);
    const auto rows = read_csv(dir / "pm.passes.csv");
    ASSERT_EQ(rows.size(), 9u);
    // The named metric (relMSE by default, docs/metrics.md) and its noise floor follow the linear columns.
    EXPECT_EQ(rows[0], (std::vector<std::string>{"pass", "spp", "elapsed_s", "seconds", "passes", "image_mean", "rel_rmse",
                                                 "rel_mean_error", "relMSE", "relMSE_noise_floor"}));
    for (size_t i = 1; i < rows.size(); ++i) {
        ASSERT_EQ(rows[i].size(), 10u);
        EXPECT_EQ(rows[i][4], "1");   // photon-map passes are one per group (each has its own map)
        EXPECT_EQ(std::stoi(rows[i][0]), int(i));
        EXPECT_EQ(std::stoi(rows[i][1]), int(i));
        EXPECT_GE(std::stod(rows[i][2]), i > 1 ? std::stod(rows[i - 1][2]) : 0.0);
    }
    // Averaging passes lowers the error (fixed seed: deterministic, not a statistical claim).
    EXPECT_LT(std::stod(rows.back()[6]), std::stod(rows[1][6]));
    std::ifstream in(dir / "pm.json");
    const auto j = nlohmann::json::parse(in);
    EXPECT_EQ(j["passes"]["count"].get<int>(), 8);
    EXPECT_NEAR(j["reference"]["rel_rmse"].get<double>(), std::stod(rows.back()[6]), 1e-8);
    // A reference of the wrong size is one clear error and writes nothing.
    EXPECT_NE(run_vpm("render " + config + " -q --set render.width=8 --set render.height=8 --reference " +
                          (dir / "ref.exr").string() + " -o " + (dir / "bad.exr").string(),
                      dir),
              0);
    EXPECT_FALSE(fs::exists(dir / "bad.exr"));
}

// Issue 24: a NaN or zero-mean reference is refused before the first pass, naming the file.
TEST(RenderPassesCli, BadReferenceIsRefusedBeforeTheWork) {
    const vpm::test::ScratchDir scratch;
    const fs::path& dir = scratch.path;
    const std::string config = std::string(VPM_SOURCE_DIR) + "/configs/homogeneous.toml";
    vpm::Image ref(8, 8);
    vpm::write_exr(dir / "zero.exr", ref);
    ref.rgb.assign(ref.rgb.size(), 0.5f);
    ref.rgb[7] = std::nanf("");
    vpm::write_exr(dir / "nan.exr", ref);
    for (const char* name : {"zero.exr", "nan.exr"}) {
        EXPECT_EQ(run_vpm("render " + config + " --set render.width=8 --set render.height=8 "
                          "--set render.integrator=photon_map --reference " + (dir / name).string() + " -o " +
                              (dir / "bad.exr").string(),
                          dir),
                  1);
        const std::string err = read_text(dir / "stderr.txt");
        EXPECT_NE(err.find(std::string(name) + ": --reference: the reference image has "), std::string::npos) << err;
        EXPECT_EQ(err.find("photons:"), std::string::npos) << err;   // no photon pass was started
        EXPECT_FALSE(fs::exists(dir / "bad.exr"));
        EXPECT_FALSE(fs::exists(dir / "bad.passes.csv"));
    }
}

// Issue 24: render.time_limit made a sidecar entry, a log line and a record per pass without bound
// (16x16, 4 spp, 2 s: 19,616 passes, 19,625 stderr lines, a 1.26 MB sidecar). Now the path
// tracer's passes go in groups of at least 65536 camera samples, the sidecar keeps the first 256
// passes and a summary, the log a line per power of two, and OUT.passes.csv a row per group.
TEST(RenderPassesCli, TimeLimitKeepsRecordsBounded) {
    const vpm::test::ScratchDir scratch;
    const fs::path& dir = scratch.path;
    const std::string config = std::string(VPM_SOURCE_DIR) + "/configs/homogeneous.toml";
    ASSERT_EQ(run_vpm("render " + config + " --threads 2 --set render.width=8 --set render.height=8 "
                      "--set render.spp=1 --set render.time_limit=1 -o " + (dir / "t.exr").string(),
                      dir),
              0) << read_text(dir / "stderr.txt");
    const std::string err = read_text(dir / "stderr.txt");
    const auto j = nlohmann::json::parse(read_text(dir / "t.json"));
    const uint64_t passes = j["passes"]["count"].get<uint64_t>();
    EXPECT_GT(passes, 256u);   // 64 samples per pass: many thousands of passes in a second
    EXPECT_EQ(j["passes"]["recorded"].get<uint64_t>(), 256u);
    EXPECT_EQ(j["passes"]["seconds"].size(), 256u);
    EXPECT_EQ(j["passes"]["image_mean"].size(), 256u);
    EXPECT_GT(j["passes"]["image_mean_mean"].get<double>(), 0.0);
    EXPECT_LT(read_text(dir / "t.json").size(), 64u * 1024u);
    EXPECT_LT(std::count(err.begin(), err.end(), '\n'), 60) << err;   // log2(passes) pass lines and a few more
    // One row per group, of up to 1024 passes here (65536 samples / 64), adding up to the count.
    const auto rows = read_csv(dir / "t.passes.csv");
    ASSERT_GE(rows.size(), 3u);
    uint64_t sum = 0, largest = 0;
    for (size_t i = 1; i < rows.size(); ++i) {
        ASSERT_EQ(rows[i].size(), 6u);
        const uint64_t n = std::stoull(rows[i][4]);
        sum += n;
        largest = std::max(largest, n);
        EXPECT_EQ(std::stoull(rows[i][0]), sum);
        EXPECT_LE(n, 1024u);
    }
    EXPECT_EQ(sum, passes);
    EXPECT_EQ(rows[1][4], "1");   // the configured pass alone, then groups of up to 1024
    EXPECT_EQ(largest, 1024u);
    EXPECT_EQ(std::stoull(rows.back()[1]), passes);   // 1 spp per pass
}
