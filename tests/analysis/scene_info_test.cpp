// vpm info's facts (lib/analysis/scene_info.h): a homogeneous sphere's optical thickness across its
// centre is 2 R sigma_t, what the camera sees adds up, and VDB files (the repository's own and,
// when present, the shared smoke sample) report their grids.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "analysis/scene_info.h"
#include "render/run/run_config.h"

namespace fs = std::filesystem;

namespace vpm {
namespace {

const char* kSphere = R"(
[render]
width = 32
height = 32
spp = 1
[camera]
position = [0.0, 0.0, 4.0]
look_at = [0.0, 0.0, 0.0]
fov = 40
[[lights]]
type = "point"
position = [0.0, 3.0, 0.0]
intensity = 10.0
[[media]]
type = "homogeneous"
shape = "sphere"
center = [0.0, 0.0, 0.0]
radius = 1.0
sigma_t_scale = 2.0
albedo = 0.9
g = 0.3
)";

TEST(SceneInfo, HomogeneousSphereThicknessAndWhatTheCameraSees) {
    const fs::path file = fs::temp_directory_path() / ("vpm_scene_info_" + std::to_string(::getpid()) + ".toml");
    std::ofstream(file) << kSphere;
    const nlohmann::json j = scene_info(RunConfig::load(file.string()));
    fs::remove(file);
    ASSERT_EQ(j["media"].size(), 1u);
    const auto& m = j["media"][0];
    EXPECT_EQ(m["type"], "homogeneous");
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(m["tau_across"][a].get<double>(), 4.0, 1e-3);   // 2 R sigma_t
    EXPECT_NEAR(m["sigma_t_max"].get<double>(), 2.0, 1e-12);
    ASSERT_EQ(j["lights"].size(), 1u);
    // A point light's power into the scene is I times the solid angle of the scene's box: from
    // (0, 3, 0) the top face of [-1, 1]^3 at distance 2, 4 asin(1 / 5) sr.
    EXPECT_NEAR(j["lights"][0]["power"][0].get<double>(), 10.0 * 4.0 * std::asin(0.2), 1e-9);
    const auto& s = j["camera"]["seen"];
    EXPECT_EQ(s["rays"], 32 * 32);
    EXPECT_NEAR(s["medium"].get<double>() + s["surface_only"].get<double>() + s["nothing"].get<double>(), 1.0, 1e-12);
    // The unit sphere at distance 4 subtends a half-angle of asin(1/4) = 14.5 degrees in a 40-degree
    // view: a disc of radius tan(14.5)/tan(20) = 0.71 of the half-width, pi 0.71^2 / 4 = 0.40 of the image.
    EXPECT_NEAR(s["medium"].get<double>(), 0.40, 0.03);
    EXPECT_EQ(s["surface_only"].get<double>(), 0.0);
    EXPECT_TRUE(j["shapes"].is_null());
    EXPECT_NE(info_text(j).find("camera sees"), std::string::npos);
}

void expect_density_grid(const nlohmann::json& j) {
    ASSERT_FALSE(j["grids"].empty());
    const auto& g = j["grids"][0];
    ASSERT_TRUE(g.contains("active_voxels")) << g.dump();
    EXPECT_GT(g["active_voxels"].get<int64_t>(), 0);
    EXPECT_GT(g["density_max"].get<double>(), 0.0);
    EXPECT_GE(g["density_min"].get<double>(), 0.0);
    for (int a = 0; a < 3; ++a) EXPECT_GT(g["voxel_size"][a].get<double>(), 0.0);
    ASSERT_TRUE(j.contains("suggested_camera"));
    // The suggested camera looks at the centre of the world bounds.
    const auto& b = g["world_bounds"];
    for (int a = 0; a < 3; ++a)
        EXPECT_NEAR(j["suggested_camera"]["look_at"][a].get<double>(),
                    0.5 * (b["lo"][a].get<double>() + b["hi"][a].get<double>()), 1e-9);
    EXPECT_NE(info_text(j).find("active voxels"), std::string::npos);
}

TEST(SceneInfo, RepositoryVdb) { expect_density_grid(vdb_info(VPM_SOURCE_DIR "/media/plume.vdb")); }

TEST(SceneInfo, SharedSmokeSampleWhenPresent) {
    const fs::path smoke = fs::path(VPM_SOURCE_DIR).parent_path() / "shared" / "samples" / "smoke.vdb";
    if (!fs::exists(smoke)) GTEST_SKIP() << smoke << " is absent (the shared samples are not part of the repository)";
    const nlohmann::json j = vdb_info(smoke.string());
    expect_density_grid(j);
    EXPECT_EQ(j["grids"][0]["type"], "double");
}

}  // namespace
}  // namespace vpm
