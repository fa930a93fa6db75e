// Camera paths that follow both events at their first glass hit (photons.glass_splits,
// render/photon_map/camera_path.h): the same mean as one event chosen by Fresnel, and far less
// variance where the camera sees a lamp by a reflection the Fresnel choice takes with probability F.
// The scene has glass, two sphere lamps and a sky and nothing the maps answer for, so every camera
// sample is an independent path (no map is queried) and the standard errors are the samples'. The
// gather is pinned: "auto"'s plan would render a scene without media or diffuse surfaces with the
// path tracer.
#include <gtest/gtest.h>

#include <string>

#include "core/error.h"
#include "core/sampling/rng.h"
#include "render/run/run.h"
#include "render/run/run_config.h"
#include "support/sample_statistics.h"

using namespace vpm;
using vpm::test::Sample;

namespace {

// A glass sphere (radius 0.6, ior 1.5) under a sky of 1. Ray A hits it at (0.3, 0, 0.52), where the
// reflection (F = 0.042) leaves along (0.866, 0, 0.5) into lamp 1; ray B goes through its centre,
// its refraction on into lamp 2 behind the sphere, its reflection (F = 0.04) back to the sky.
const char* kLampsAndGlass = R"(
[render]
integrator = "photon_map"
[camera]
position = [0, 0, 4]
look_at = [0, 0, 0]
[[lights]]
type = "environment"
radiance = 1
[[lights]]
type = "sphere"
center = [2.898, 0, 2.02]
radius = 0.4
radiance = 50
[[lights]]
type = "sphere"
center = [0, 0, -3]
radius = 0.5
radiance = 50
[[shapes]]
type = "sphere"
center = [0, 0, 0]
radius = 0.6
material = "dielectric"
ior = 1.5
[photons]
count = 1000
gather = "collision"
)";

const Ray kReflectsLamp{Vec3(0.3, 0, 4), Vec3(0, 0, -1)};
const Ray kRefractsToLamp{Vec3(0, 0, 4), Vec3(0, 0, -1)};

// n camera samples along `ray`, each with its own stream.
Sample samples(const std::string& splits, const Ray& ray, uint64_t seed) {
    const RunConfig config =
        RunConfig::build(parse_config(kLampsAndGlass, "lamps_glass.toml", ".", {"photons.glass_splits=" + splits}));
    auto integrator = config.create_integrator();
    RunStats stats;
    PassContext context;
    context.progress = false;
    integrator->prepare(context, stats);
    Sample s;
    for (int i = 0; i < 20000; ++i) {
        Rng rng(seed, uint64_t(i));
        s.add(integrator->radiance(ray, rng)[1]);
    }
    return s;
}

}  // namespace

TEST(CameraPathGlassSplit, SameMeanAsOneFresnelChoiceAndLessVarianceWhereALampIsSeenInTheGlass) {
    // Ray A sees lamp 1 at its first glass hit, ray B lamp 2 after its second (the exit): one split
    // removes ray A's choice, two splits ray B's.
    const struct {
        const Ray& ray;
        const char* splits_that_see_it;
    } cases[] = {{kReflectsLamp, "1"}, {kRefractsToLamp, "2"}};
    uint64_t seed = 7;
    for (const auto& c : cases) {
        const Sample one = samples("0", c.ray, seed++);
        for (const char* splits : {"1", "2"}) {
            const Sample both = samples(splits, c.ray, seed++);
            const double se = std::hypot(one.se(), both.se());
            EXPECT_NEAR(both.mean(), one.mean(), 4.0 * se) << "glass_splits " << splits << ": " << both.mean() << " +- "
                                                           << both.se() << ", one event " << one.mean() << " +- " << one.se();
            // Decisive against a branch weighed 1 instead of F or 1 - F: lamp 1 alone would add ~48
            // on ray A, and ray B's lamp weighs (1 - F)^2 = 0.92 of 50, 2 below its weight without F.
            EXPECT_LT(se, 0.2);
            if (std::string(splits) == c.splits_that_see_it) {
                EXPECT_LT(both.var(), 0.1 * one.var()) << "glass_splits " << splits << " var " << both.var() << ", one event "
                                                       << one.var();
            }
        }
    }
}

TEST(CameraPathGlassSplit, SplitsOutsideZeroToFourAreOneConfigErrorNamingTheKey) {
    for (const char* bad : {"-1", "5", "1.5", "true"}) {
        try {
            RunConfig::build(parse_config(kLampsAndGlass, "lamps_glass.toml", ".", {std::string("photons.glass_splits=") + bad}));
            FAIL() << "accepted photons.glass_splits = " << bad;
        } catch (const ConfigError& e) {
            EXPECT_NE(std::string(e.what()).find("glass_splits"), std::string::npos) << e.what();
        }
    }
}
