// The march (and beam) gathers weigh the sky seen through the medium by a transmittance estimate
// instead of the free flight's Bernoulli trial (PhotonMapIntegrator::trace): still the path
// tracer's image in the mean, and the per-pixel noise of a thin sky-lit sphere falls below the
// collision gather's (before: 28x above it, the trial's T (1 - T) L^2).
#include <gtest/gtest.h>

#include <cmath>

#include "config/params.h"
#include "render/run/run.h"
#include "render/run/run_config.h"
#include "support/render_statistics.h"

using namespace vpm;

namespace {

RunConfig sky_sphere(const std::string& integrator, const std::string& gather) {
    const std::string text =
        "[render]\nwidth = 12\nheight = 12\nspp = 16\n[camera]\nposition = [0, 0, 4]\nlook_at = [0, 0, 0]\nfov = 30\n"
        "[[lights]]\ntype = 'environment'\nradiance = 1\n"
        "[[media]]\ntype = 'homogeneous'\nshape = 'sphere'\nradius = 1\nsigma_t_scale = 0.5\nalbedo = 0.9\ng = 0\n";
    return RunConfig::build(parse_config(text, "sky_sphere.toml", ".",
                                         {"render.integrator=\"" + integrator + "\"", "photons.count=60000",
                                          "photons.gather=\"" + gather + "\""}));
}

// Mean squared difference of the green channel between two independent runs: twice a pixel's variance.
double pixel_noise(const RunConfig& config) {
    RunOptions a, b;
    a.progress = b.progress = false;
    b.stream_offset = 1;
    const Image x = run(config, a).image, y = run(config, b).image;
    double sum = 0.0;
    for (size_t i = 1; i < x.rgb.size(); i += 3) sum += double(x.rgb[i] - y.rgb[i]) * double(x.rgb[i] - y.rgb[i]);
    return sum / double(x.rgb.size() / 3);
}

}  // namespace

TEST(MarchUnderASky, SeesTheSkyThroughTheMediumUnbiasedAndWithLessNoise) {
    const test::Sample pt = test::repeated_run_brightness(sky_sphere("path", "collision"), 6);
    for (const char* gather : {"march", "beam"}) {
        const test::Sample pm = test::repeated_run_brightness(sky_sphere("photon_map", gather), 6);
        const double z = (pm.mean() - pt.mean()) / std::hypot(pm.se(), pt.se());
        std::printf("%s: photon map %.5f +- %.5f, path tracer %.5f +- %.5f, z %.2f\n", gather, pm.mean(), pm.se(), pt.mean(),
                    pt.se(), z);
        EXPECT_LT(std::abs(z), 3.0) << gather;
    }
    const double march = pixel_noise(sky_sphere("photon_map", "march"));
    const double collision = pixel_noise(sky_sphere("photon_map", "collision"));
    std::printf("pixel noise: march %.3g, collision %.3g\n", march, collision);
    EXPECT_LT(march, 0.5 * collision);
}
