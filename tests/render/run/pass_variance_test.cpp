// RunOptions::pass_variance (render/run/run.h): the variance image a multi-pass run keeps predicts
// the spread between two independent runs, E[(Y_A - Y_B)^2] = var_A + var_B per pixel, for the path
// tracer and for the photon map (whose passes each trace their own photon map).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "config/params.h"
#include "render/run/run.h"
#include "render/run/run_config.h"

namespace vpm {
namespace {

const char* kScene = R"(
[render]
width = 24
height = 24
spp = 8
passes = 8
seed = 5
[camera]
position = [0.0, 0.0, 4.0]
look_at = [0.0, 0.0, 0.0]
fov = 40
[[lights]]
type = "spot"
position = [-2.0, 3.0, 1.0]
look_at = [0.0, 0.0, 0.0]
intensity = 30.0
cone_angle = 25
[[media]]
type = "homogeneous"
shape = "sphere"
center = [0.0, 0.0, 0.0]
radius = 1.0
sigma_t_scale = 2.0
albedo = 0.9
g = 0.3
[photons]
count = 2000
k = 8
)";

double lum(const Image& im, size_t p) { return 0.2126 * im.rgb[3 * p] + 0.7152 * im.rgb[3 * p + 1] + 0.0722 * im.rgb[3 * p + 2]; }

RunResult render(const std::string& integrator, uint64_t stream_offset, bool variance, int passes = 8) {
    const auto doc = parse_config(kScene, "pass_variance_test.toml", std::filesystem::temp_directory_path(),
                                  {"render.integrator=\"" + integrator + "\"", "render.passes=" + std::to_string(passes)});
    RunOptions o;
    o.progress = false;
    o.stream_offset = stream_offset;
    o.pass_variance = variance;
    return run(RunConfig::build(doc), o);
}

TEST(PassVariance, PredictsTheSpreadBetweenIndependentRuns) {
    for (const std::string integrator : {"path", "photon_map"}) {
        const RunResult a = render(integrator, 0, true), b = render(integrator, 1, true);
        ASSERT_EQ(a.variance.width, 24) << integrator;
        ASSERT_EQ(b.variance.height, 24) << integrator;
        const size_t P = 24 * 24;
        std::vector<double> term(P);
        double mean = 0, predicted = 0;
        for (size_t p = 0; p < P; ++p) {
            const double d = lum(a.image, p) - lum(b.image, p);
            EXPECT_EQ(a.variance.rgb[3 * p], a.variance.rgb[3 * p + 2]);   // grey
            EXPECT_GE(a.variance.rgb[3 * p], 0.0f);
            term[p] = d * d - (a.variance.rgb[3 * p] + b.variance.rgb[3 * p]);
            mean += term[p] / double(P);
            predicted += (a.variance.rgb[3 * p] + b.variance.rgb[3 * p]) / double(P);
        }
        double var = 0;
        for (double t : term) var += (t - mean) * (t - mean) / double(P - 1);
        const double se = std::sqrt(var / double(P));
        EXPECT_GT(predicted, 0.0) << integrator;
        EXPECT_NEAR(mean, 0.0, 3.0 * se) << integrator << ": predicted spread " << predicted;
    }
}

TEST(PassVariance, NoneForOnePassOrWhenNotAsked) {
    EXPECT_EQ(render("path", 0, true, 1).variance.width, 0);
    EXPECT_EQ(render("path", 0, false).variance.width, 0);
}

}  // namespace
}  // namespace vpm
