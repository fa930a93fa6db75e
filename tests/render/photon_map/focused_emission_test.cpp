// Issue 24: a sky over a scene much wider than what the camera sees. The camera looks down at a
// small patch of a thin slab 20,000 wide lit by the sky and by a point light above the patch. The
// importance allocation gives the point light most photons, and the sky's photons, spread over the
// whole slab, almost never landed near the patch: the photon map lost the sky's multiple
// scattering there (0.229 against the path tracer's 0.424). Lights at infinity now aim nested
// shares of their photons at what the camera sees (scene/lights/emission_bounds.h).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iostream>
#include <string>

#include "support/io_test_util.h"
#include "support/render_statistics.h"

using namespace vpm;

namespace {

class FocusedEmission : public vpm_test::TempDirTest {
protected:
    // Mean image over `passes` passes of `spp` samples per pixel, each pass its own photon map.
    test::Sample brightness(const std::string& integrator, int passes, int spp) {
        const auto path = dir_ / "slab.toml";
        std::ofstream(path) << R"(
[render]
width = 16
height = 16
spp = 16
integrator = ")" << integrator << R"("
[camera]
position = [0, 4, 0.5]
look_at = [0, 0, 0]
fov = 30
[photons]
count = 100000
k = 32
[[lights]]
type = "point"
position = [0, 2.5, 0]
intensity = 1
[[lights]]
type = "environment"
radiance = 0.5
[[media]]
type = "homogeneous"
shape = "box"
min = [-10000, 0, -10000]
max = [10000, 2, 10000]
sigma_t_scale = 1
albedo = 0.9
)";
        return test::pass_brightness(RunConfig::load(
            path.string(), {"render.spp=" + std::to_string(passes * spp), "render.passes=" + std::to_string(passes)}));
    }
};

}  // namespace

// The photon map against the path tracer within 3 standard errors of the difference (64 maps of
// 1e5 photons: -0.14% +- 0.38%).
TEST_F(FocusedEmission, SkyOverAWideSlabMatchesThePathTracer) {
    const test::Sample photon_map = brightness("photon_map", 32, 4);
    const test::Sample path = brightness("path", 32, 8);
    const double se = std::hypot(photon_map.se(), path.se());
    std::cout << "photon map " << photon_map.mean() << " +- " << photon_map.se() << ", path tracer " << path.mean()
              << " +- " << path.se() << "\n";
    EXPECT_NEAR(photon_map.mean(), path.mean(), 3.0 * se);
    EXPECT_LT(se, 0.01 * path.mean()) << "too noisy to tell 3%";
}
