// vpm info's facts (lib/analysis/scene_info.h): a homogeneous sphere's optical thickness across its
// centre is 2 R sigma_t, what the camera sees adds up, and VDB files (the repository's own and,
// when present, the shared smoke sample) report their grids.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "analysis/density_extent.h"
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

// The share of pixels in which the suggested camera sees the grid (vpm info's "camera sees" of a
// scene made of that file and camera).
double seen_through_suggested_camera(const nlohmann::json& j, const std::string& vdb) {
    const auto& c = j["suggested_camera"];
    auto list = [](const nlohmann::json& v) { return "[" + v[0].dump() + ", " + v[1].dump() + ", " + v[2].dump() + "]"; };
    const fs::path file = fs::temp_directory_path() / ("vpm_scene_info_camera_" + std::to_string(::getpid()) + ".toml");
    std::ofstream(file) << "[render]\nwidth = 48\nheight = 48\nspp = 1\n[camera]\nposition = " << list(c["position"])
                        << "\nlook_at = " << list(c["look_at"]) << "\nfov = " << c["fov"].dump()
                        << "\n[[lights]]\ntype = \"environment\"\nradiance = 1.0\n[[media]]\ntype = \"grid\"\nfile = \"" << vdb
                        << "\"\ngrid = \"" << j["grids"][0]["name"].get<std::string>() << "\"\nsigma_t_scale = 10.0\n";
    const nlohmann::json scene = scene_info(RunConfig::load(file.string()));
    fs::remove(file);
    return scene["camera"]["seen"]["medium"].get<double>();
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
    // Where the density is lies inside the grid's box, holds nearly all of it, and the suggested
    // camera looks at its centre (not at the box's).
    EXPECT_GT(g["nonzero_voxels"].get<int64_t>(), 0);
    EXPECT_GE(g["mass_inside"].get<double>(), 1.0 - 6 * 0.001);
    const auto& b = g["world_bounds"];
    const auto& m = g["mass_bounds"];
    const auto& d = g["density_bounds"];
    for (int a = 0; a < 3; ++a) {
        EXPECT_GE(m["lo"][a].get<double>(), d["lo"][a].get<double>() - 1e-9);
        EXPECT_LE(m["hi"][a].get<double>(), d["hi"][a].get<double>() + 1e-9);
        EXPECT_GE(d["lo"][a].get<double>(), b["lo"][a].get<double>() - 1e-9);
        EXPECT_LE(d["hi"][a].get<double>(), b["hi"][a].get<double>() + 1e-9);
        EXPECT_NEAR(j["suggested_camera"]["look_at"][a].get<double>(),
                    0.5 * (m["lo"][a].get<double>() + m["hi"][a].get<double>()), 1e-9);
    }
    EXPECT_NE(info_text(j).find("active voxels"), std::string::npos);
    EXPECT_NE(info_text(j).find("of the density in"), std::string::npos);
}

TEST(SceneInfo, RepositoryVdb) {
    for (const char* file : {VPM_SOURCE_DIR "/media/plume.vdb", VPM_SOURCE_DIR "/tests/data/vdb/puff.vdb"}) {
        const nlohmann::json j = vdb_info(file);
        expect_density_grid(j);
        // The bounding sphere of the density fills the 40-degree view: the medium covers a good part of it.
        EXPECT_GT(seen_through_suggested_camera(j, file), 0.15) << file;
    }
}

TEST(SceneInfo, SharedSmokeSampleWhenPresent) {
    const fs::path smoke = fs::path(VPM_SOURCE_DIR).parent_path() / "shared" / "samples" / "smoke.vdb";
    if (!fs::exists(smoke)) GTEST_SKIP() << smoke << " is absent (the shared samples are not part of the repository)";
    const nlohmann::json j = vdb_info(smoke.string());
    expect_density_grid(j);
    EXPECT_EQ(j["grids"][0]["type"], "double");
    // Its 128 x 64 x 64 active voxels hold density in an 8^3 corner: the box's camera saw it in 0.3% of the pixels.
    EXPECT_GT(seen_through_suggested_camera(j, smoke.string()), 0.15);
}

// Density in a 3^3 block of a 64^3 grid, and a trace of haze far away: the non-zero box holds both,
// the mass box only the block.
TEST(DensityExtent, NonZeroBoxAndMassBox) {
    DensityGrid g(Vec3i(0, 0, 0), Vec3i(63, 63, 63));
    for (int z = 10; z <= 12; ++z)
        for (int y = 10; y <= 12; ++y)
            for (int x = 10; x <= 12; ++x) g.set_voxel(Vec3i(x, y, z), 1.0f);
    g.set_voxel(Vec3i(60, 60, 60), 1e-6f);
    g.finalize();
    const DensityExtent e = density_extent(g);
    EXPECT_EQ(e.nonzero_voxels, 28);
    EXPECT_NEAR(e.total, 27.0, 1e-5);
    for (int a = 0; a < 3; ++a) {
        EXPECT_NEAR(e.nonzero.lo[a], 9.5, 1e-12);
        EXPECT_NEAR(e.nonzero.hi[a], 60.5, 1e-12);
        EXPECT_NEAR(e.mass.lo[a], 9.5, 1e-12);
        EXPECT_NEAR(e.mass.hi[a], 12.5, 1e-12);
    }
    EXPECT_NEAR(e.mass_inside, 1.0, 1e-6);
    EXPECT_EQ(density_extent(DensityGrid()).nonzero_voxels, 0);
}

}  // namespace
}  // namespace vpm
