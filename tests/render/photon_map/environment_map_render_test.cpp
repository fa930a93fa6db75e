// An environment map of constant value renders the same as the constant sky of that radiance
// (issue 16): the same scattering sphere on a floor under each, path tracer and photon map, mean
// image brightness over independent runs within three combined standard errors. The two lights
// sample directions differently (the map by texel, the sky uniformly), so equal means test the
// map's weights, pdf and photon power, not a shared code path. The camera looks down at the floor,
// so no pixel shows the sky itself (which would be exact and dilute the comparison).
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <string>

#include "render/run/image_io.h"
#include "render/run/run.h"
#include "support/io_test_util.h"
#include "support/render_statistics.h"

using namespace vpm;

namespace {

class EnvironmentMapRender : public vpm_test::TempDirTest {
protected:
    test::Sample brightness(const std::string& light, const std::string& integrator, int repeats) {
        const std::string text = R"(
[render]
width = 24
height = 24
spp = 8
integrator = ")" + integrator + R"("
[camera]
position = [0, 3, 3]
look_at = [0, 0.5, 0]
fov = 45
[photons]
count = 80000
k = 16
estimator = "corrected"
[[lights]]
type = "environment"
)" + light + R"(
[[media]]
type = "homogeneous"
shape = "sphere"
center = [0, 0.8, 0]
radius = 0.7
sigma_t_scale = 3
albedo = 0.8
g = 0.3
[[shapes]]
type = "quad"
center = [0, 0, 0]
u = [6, 0, 0]
v = [0, 0, -6]
reflectance = 0.5
)";
        return test::repeated_run_brightness(RunConfig::build(parse_config(text, "env.toml", dir_)), repeats);
    }
};

}  // namespace

TEST_F(EnvironmentMapRender, ConstantMapRendersLikeTheConstantSky) {
    Image map(32, 16);
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 32; ++x) map.set(x, y, Rgb(0.3, 0.6, 0.9));
    write_exr(dir_ / "constant.exr", map);
    for (const std::string integrator : {"path", "photon_map"}) {
        const test::Sample sky = brightness("radiance = [0.6, 1.2, 1.8]", integrator, 16);
        const test::Sample env = brightness("file = 'constant.exr'\nscale = 2\nrotate_y = 33", integrator, 16);
        const double se = std::hypot(sky.se(), env.se());
        std::cout << integrator << ": constant sky " << sky.mean() << " +- " << sky.se() << ", constant map "
                  << env.mean() << " +- " << env.se() << "\n";
        EXPECT_NEAR(env.mean(), sky.mean(), 3.0 * se) << integrator;
        EXPECT_LT(se, 0.01 * sky.mean()) << integrator << ": too noisy to tell";
    }
}
