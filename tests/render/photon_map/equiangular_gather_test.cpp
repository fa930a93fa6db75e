// render.equiangular in the photon map's camera paths (transport/equiangular.h): with a point light
// inside a medium, every gather (collision, march, beam) gives the same image mean with and without
// the equiangular sample, within the standard errors over independent runs (the map is the same in
// both: the photon pass draws from its own streams), and render.equiangular = false draws exactly
// the random numbers it did before (scripts/images_identical.sh, docs/equiangular.md).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "config/params.h"
#include "render/run/run.h"
#include "render/run/run_config.h"
#include "support/render_statistics.h"

using namespace vpm;

namespace {

RunConfig inside(const std::string& gather, bool equiangular) {
    const std::string text =
        "[render]\nwidth = 10\nheight = 10\nspp = 8\nintegrator = 'photon_map'\n"
        "[camera]\nposition = [0, 0, 3]\nlook_at = [0, 0, 0]\nfov = 40\n"
        "[photons]\ncount = 20000\nk = 16\n"
        "[[lights]]\ntype = 'point'\nposition = [0.1, 0.2, 0.0]\nintensity = 1\n"
        "[[media]]\ntype = 'homogeneous'\nshape = 'sphere'\nradius = 1\nsigma_t_scale = 2\nalbedo = 0.8\ng = 0.3\n";
    return RunConfig::build(parse_config(text, "equiangular.toml", ".",
                                         {"photons.gather=\"" + gather + "\"",
                                          std::string("render.equiangular=") + (equiangular ? "true" : "false")}));
}

}  // namespace

TEST(EquiangularGather, EveryGatherAgreesWithDistanceSamplingAlone) {
    const int repeats = 6;
    for (const char* gather : {"collision", "march", "beam"}) {
        const test::Sample on = test::repeated_run_brightness(inside(gather, true), repeats);
        const test::Sample off = test::repeated_run_brightness(inside(gather, false), repeats);
        const double z = (on.mean() - off.mean()) / std::sqrt(on.se() * on.se() + off.se() * off.se());
        std::printf("gather %s: equiangular %.5f +- %.5f, distance only %.5f +- %.5f, z %.2f\n", gather, on.mean(), on.se(),
                    off.mean(), off.se(), z);
        EXPECT_GT(on.mean(), 0.0) << gather;
        EXPECT_LT(std::abs(z), 4.0) << gather;
    }
}
