// `vpm render --reference REF.exr` with passes: the error of the mean so far after every pass, in
// OUT.passes.csv and the sidecar.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include <nlohmann/json.hpp>

namespace fs = std::filesystem;

namespace {

int run_vpm(const std::string& args, const fs::path& dir) {
    const std::string cmd = std::string(VPM_BINARY) + " " + args + " 2> " + (dir / "stderr.txt").string() + " > /dev/null";
    return WEXITSTATUS(std::system(cmd.c_str()));
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
    const fs::path dir = fs::temp_directory_path() / "vpm_render_passes_cli";
    fs::remove_all(dir);
    fs::create_directories(dir);
    const std::string config = std::string(VPM_SOURCE_DIR) + "/configs/homogeneous.toml";
    const std::string small = " -q --set render.width=16 --set render.height=16 ";
    ASSERT_EQ(run_vpm("render " + config + small + "--set render.spp=64 -o " + (dir / "ref.exr").string(), dir), 0);
    ASSERT_EQ(run_vpm("render " + config + small +
                          "--set render.integrator=photon_map --set photons.count=5000 --set render.spp=8 "
                          "--set render.passes=8 --reference " + (dir / "ref.exr").string() + " -o " +
                          (dir / "pm.exr").string(),
                      dir),
              0);
    const auto rows = read_csv(dir / "pm.passes.csv");
    ASSERT_EQ(rows.size(), 9u);
    EXPECT_EQ(rows[0], (std::vector<std::string>{"pass", "spp", "elapsed_s", "rel_rmse", "rel_mean_error"}));
    for (size_t i = 1; i < rows.size(); ++i) {
        ASSERT_EQ(rows[i].size(), 5u);
        EXPECT_EQ(std::stoi(rows[i][0]), int(i));
        EXPECT_EQ(std::stoi(rows[i][1]), int(i));
        EXPECT_GE(std::stod(rows[i][2]), i > 1 ? std::stod(rows[i - 1][2]) : 0.0);
    }
    // Averaging passes lowers the error (fixed seed: deterministic, not a statistical claim).
    EXPECT_LT(std::stod(rows.back()[3]), std::stod(rows[1][3]));
    std::ifstream in(dir / "pm.json");
    const auto j = nlohmann::json::parse(in);
    EXPECT_EQ(j["passes"]["count"].get<int>(), 8);
    EXPECT_NEAR(j["reference"]["rel_rmse"].get<double>(), std::stod(rows.back()[3]), 1e-8);
    // A reference of the wrong size is one clear error and writes nothing.
    EXPECT_NE(run_vpm("render " + config + " -q --set render.width=8 --set render.height=8 --reference " +
                          (dir / "ref.exr").string() + " -o " + (dir / "bad.exr").string(),
                      dir),
              0);
    EXPECT_FALSE(fs::exists(dir / "bad.exr"));
    fs::remove_all(dir);
}
