// `vpm info`: --help, a config and a VDB from the command line, --json, and bad input.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "support/vpm_process.h"

using namespace vpm::test;

TEST(InfoCli, HelpConfigVdbAndBadInput) {
    ScratchDir dir;
    Outcome o = run_vpm("info --help", dir.path);
    EXPECT_EQ(o.code, 0);
    EXPECT_NE(o.out.find("VDB"), std::string::npos) << o.out;
    o = run_vpm("info " + quote(std::string(VPM_SOURCE_DIR) + "/configs/default.toml"), dir.path);
    ASSERT_EQ(o.code, 0) << o.err;
    EXPECT_NE(o.out.find("world bounds"), std::string::npos) << o.out;
    EXPECT_NE(o.out.find("camera sees"), std::string::npos) << o.out;
    o = run_vpm("info --json " + quote(std::string(VPM_SOURCE_DIR) + "/media/plume.vdb"), dir.path);
    ASSERT_EQ(o.code, 0) << o.err;
    const nlohmann::json j = nlohmann::json::parse(o.out);
    EXPECT_EQ(j["kind"], "vdb");
    EXPECT_GT(j["grids"][0]["active_voxels"].get<int64_t>(), 0);
    // A --set on a VDB, a bad key and a missing file: one error line, non-zero exit.
    o = run_vpm("info --set photons.k=4 " + quote(std::string(VPM_SOURCE_DIR) + "/media/plume.vdb"), dir.path);
    EXPECT_EQ(o.code, 2) << o.err;
    EXPECT_TRUE(o.one_line()) << o.err;
    o = run_vpm("info --set camera.fov=400 " + quote(std::string(VPM_SOURCE_DIR) + "/configs/default.toml"), dir.path);
    EXPECT_NE(o.code, 0);
    EXPECT_NE(o.err.find("camera.fov"), std::string::npos) << o.err;
    o = run_vpm("info " + quote(dir.path / "missing.vdb"), dir.path);
    EXPECT_NE(o.code, 0);
    EXPECT_TRUE(o.one_line()) << o.err;
}
