// vpm render --unset KEY: a key the file sets is removed so that its default or the automatic choice
// it pins applies again; under render.time_limit the log says, before the work, which pins switch
// off which automatic choice.
#include <gtest/gtest.h>

#include "support/vpm_process.h"

using namespace vpm::test;

TEST(UnsetCli, PinsAreNamedAndUnsetGivesThePlanItsChoiceBack) {
    ScratchDir dir;
    write_file(dir.path / "scene.toml", R"([render]
width = 12
height = 8
spp = 4
time_limit = 0.05
integrator = "photon_map"
[camera]
position = [0.0, 0.0, 4.0]
look_at = [0.0, 0.0, 0.0]
fov = 40
[[lights]]
type = "point"
position = [0.0, 2.0, 2.0]
intensity = 10.0
[[media]]
type = "homogeneous"
shape = "sphere"
center = [0.0, 0.0, 0.0]
radius = 1.0
sigma_t_scale = 2.0
albedo = 0.9
[photons]
count = 3000
)");
    const std::string scene = quote(dir.path / "scene.toml"), file = (dir.path / "scene.toml").string();
    auto out = [&](const char* name) { return " -o " + quote(dir.path / name); };
    Outcome o = run_vpm("render " + scene + out("a.exr"), dir.path);
    ASSERT_EQ(o.code, 0) << o.err;
    EXPECT_NE(o.err.find("pin: photons.count = 3000 (" + file + ") switches off the time limit's sizing of photons per pass"),
              std::string::npos) << o.err;
    EXPECT_NE(o.err.find("pin: render.spp = 4 (" + file + ")"), std::string::npos) << o.err;
    EXPECT_NE(read_file(dir.path / "a.json").find("\"count\": 3000"), std::string::npos);

    o = run_vpm("render " + scene + " --unset photons.count --unset render.spp" + out("b.exr"), dir.path);
    ASSERT_EQ(o.code, 0) << o.err;
    EXPECT_EQ(o.err.find("pin:"), std::string::npos) << o.err;
    EXPECT_EQ(read_file(dir.path / "b.json").find("\"count\": 3000"), std::string::npos);   // the plan sized it

    // A key the file does not set: one line naming the key and the file, nothing written.
    o = run_vpm("render " + scene + " --unset photons.k" + out("c.exr"), dir.path);
    EXPECT_EQ(o.code, 1);
    EXPECT_NE(o.err.find("--unset photons.k: " + file + " does not set it"), std::string::npos) << o.err;
    EXPECT_FALSE(fs::exists(dir.path / "c.exr"));
    o = run_vpm("render " + scene + " --unset media" + out("c.exr"), dir.path);
    EXPECT_EQ(o.code, 1);
    EXPECT_NE(o.err.find("--unset media: is a whole table"), std::string::npos) << o.err;
}
