// Smoke in a glass bottle (`interior_medium`, scene/interior_medium.h, docs/interior_medium.md):
// the furnace with the fog inside a glass sphere only reads its exact answer in the photon map and
// the path tracer, and the two agree on a lit flask, each within 3 standard errors over independent
// runs (photon maps and camera samples), fixed seeds.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "render/run/run_config.h"
#include "support/render_statistics.h"

using namespace vpm;
using vpm::test::Sample;

namespace {

// Non-absorbing fog (the table a sphere of radius 1.5) inside a clear glass sphere of radius 1
// only, under a sky of 1: the radiance is 1 everywhere outside the glass (eta^2 inside), so the
// camera outside reads exactly 1.
const char* kFurnace = R"(
[camera]
position = [0, 0, 4]
look_at = [0, 0, 0]
fov = 20
[[lights]]
type = "environment"
radiance = 1.0
[[media]]
type = "homogeneous"
shape = "sphere"
radius = 1.5
sigma_t_scale = 1.0
albedo = 1.0
g = 0.5
[[shapes]]
type = "sphere"
center = [0, 0, 0]
radius = 1.0
material = "dielectric"
ior = 1.5
interior_medium = 0
)";

// Smoke in a glass ball (the table a box larger than the ball) under a sky, lit by a sphere lamp:
// all the light in the smoke came through the glass.
const char* kFlask = R"(
[camera]
position = [0.0, 0.9, 2.2]
look_at = [0.0, 0.45, 0.0]
fov = 30
[[lights]]
type = "sphere"
center = [1.0, 1.6, 0.5]
radius = 0.3
radiance = 20.0
[[lights]]
type = "environment"
radiance = 0.3
[[media]]
type = "homogeneous"
shape = "box"
min = [-1.0, 0.0, -1.0]
max = [1.0, 1.0, 1.0]
sigma_t_scale = 3.0
albedo = 0.9
g = 0.3
[[shapes]]
type = "sphere"
center = [0.0, 0.5, 0.0]
radius = 0.45
material = "dielectric"
ior = 1.5
interior_medium = 0
)";

Sample runs(const char* text, const std::vector<std::string>& sets, int repeats) {
    std::vector<std::string> o = {"render.width=16", "render.height=16"};
    o.insert(o.end(), sets.begin(), sets.end());
    return test::repeated_run_brightness(RunConfig::build(parse_config(text, "interior_medium.toml", ".", o)), repeats);
}

const std::vector<std::string> kPhotonMap = {"render.integrator=\"photon_map\"", "photons.count=50000", "photons.k=32",
                                             "photons.estimator=\"corrected\""};

}  // namespace

TEST(InteriorMediumRender, FurnaceReadsOneInBothIntegrators) {
    // Every collision stored (direct = "photon_map"): the photon density is uniform in the glass.
    std::vector<std::string> pm = kPhotonMap;
    pm.insert(pm.end(), {"render.spp=2", "photons.direct=\"photon_map\""});
    for (const char* gather : {"photons.gather=\"collision\"", "photons.gather=\"march\""}) {
        std::vector<std::string> sets = pm;
        sets.push_back(gather);
        const Sample s = runs(kFurnace, sets, 48);
        std::printf("interior furnace, photon map, %s, 48 maps: %.5f +- %.5f\n", gather, s.mean(), s.se());
        EXPECT_NEAR(s.mean(), 1.0, 3.0 * s.se()) << gather;
        EXPECT_LT(s.se(), 0.004) << gather;   // the check resolves 1.2%
    }
    const Sample pt = runs(kFurnace, {"render.integrator=\"path\"", "render.spp=64"}, 16);
    std::printf("interior furnace, path tracer, 16 runs: %.5f +- %.5f\n", pt.mean(), pt.se());
    EXPECT_NEAR(pt.mean(), 1.0, 3.0 * pt.se());
    EXPECT_LT(pt.se(), 0.004);
}

TEST(InteriorMediumRender, PhotonMapAgreesWithThePathTracerOnAFlask) {
    std::vector<std::string> pm = kPhotonMap;
    pm.push_back("render.spp=16");
    const Sample p = runs(kFlask, pm, 32);
    const Sample t = runs(kFlask, {"render.integrator=\"path\"", "render.spp=1024"}, 16);
    const double se = std::sqrt(p.se() * p.se() + t.se() * t.se());
    std::printf("flask: photon map %.5f +- %.5f, path tracer %.5f +- %.5f, %+.2f SE\n", p.mean(), p.se(), t.mean(), t.se(),
                (p.mean() - t.mean()) / se);
    EXPECT_NEAR(p.mean(), t.mean(), 3.0 * se);
    EXPECT_LT(se, 0.01 * t.mean());   // the check resolves 3%
    EXPECT_GT(t.mean(), 0.1);          // the smoke is lit: the check is not of two black images
}
