// Issue 24, item 2: a scene scaled as a whole by s (camera, lights, media and shapes by s, densities
// by 1/s, point and spot intensities by s^2 so that I / d^2 stays) renders the same image for s from
// 1e-6 to 1e6 with both integrators: the same seed draws the same random numbers, so the images
// agree up to rounding unless some constant of the code is absolute. Before the fix the rays leaving
// a surface were offset by an absolute 1e-4 (transport/walk_steps.cpp), 100 scene sizes at s = 1e-6:
// the default plume's path-traced mean moved by +1.4% there.
#include <gtest/gtest.h>

#include <cstdio>
#include <sstream>

#include "render/run/run.h"
#include "render/run/run_config.h"

using namespace vpm;

namespace {

std::string num(double v) {
    std::ostringstream s;
    s.precision(17);
    s << v;
    return s.str();
}
std::string vec(double s, double x, double y, double z) { return "[" + num(s * x) + "," + num(s * y) + "," + num(s * z) + "]"; }

// configs/default_photon_map.toml (VDB plume, Embree floor, spot light, sky) scaled by s.
double plume_mean(double s, const char* integrator) {
    const RunConfig config = RunConfig::load(
        VPM_SOURCE_DIR "/configs/default_photon_map.toml",
        {"render.width=10", "render.height=10", "render.spp=4", "photons.count=100000",
         std::string("render.integrator=") + integrator, "camera.position=" + vec(s, 0.0, 0.85, 3.2),
         "camera.look_at=" + vec(s, 0.0, 0.7, 0.0), "lights.0.position=" + vec(s, -1.6, 2.6, 1.2),
         "lights.0.look_at=" + vec(s, 0.0, 0.6, 0.0), "lights.0.intensity=" + vec(s * s, 14.0, 12.0, 9.0),
         "media.0.sigma_t_scale=" + num(40.0 / s), "media.0.transform.scale=" + num(s),
         "shapes.0.center=" + vec(s, 0, 0, 0), "shapes.0.u=" + vec(s, 3.0, 0, 0), "shapes.0.v=" + vec(s, 0, 0, -3.0)});
    RunOptions o;
    o.progress = false;
    const RunResult r = run(config, o);
    EXPECT_EQ(r.stats.render.nonfinite_samples, 0u);
    return r.image.mean();
}

}  // namespace

TEST(ScaleInvariance, TheDefaultPlumeScaledAsAWholeRendersTheSameImage) {
    for (const char* integrator : {"path", "photon_map"}) {
        const double one = plume_mean(1.0, integrator);
        ASSERT_GT(one, 0.0);
        for (double s : {1e-6, 1e-3, 1e3, 1e6}) {
            const double scaled = plume_mean(s, integrator);
            std::printf("%s: s = %g: %.7f (s = 1: %.7f), relative %.2e\n", integrator, s, scaled, one, scaled / one - 1.0);
            // Same random numbers: the path tracer's image is the same to rounding; in the photon pass
            // rounding sends a few photon paths another way (stored counts differ by ~1e-4), which
            // moves this small image by up to ~1e-3 (measured 2e-5 .. 1.3e-3 with 20000 photons).
            const double tolerance = std::string(integrator) == "path" ? 1e-9 : 2e-3;
            EXPECT_NEAR(scaled, one, tolerance * one) << integrator << " s = " << s;
        }
    }
}
