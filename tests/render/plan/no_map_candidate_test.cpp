// The "continue" candidate (render/plan/no_map_candidate.h): where a delta light's light reaches the
// scene through mirrors or glass, the path tracer cannot find it, so the "auto" integrator does
// not offer it and renders with the photon map, whatever its pilot's noise says.
#include <gtest/gtest.h>

#include <string>

#include "render/plan/no_map_candidate.h"
#include "render/run/run.h"
#include "render/run/run_config.h"
#include "render/photon_map/photon_map_stats.h"

using namespace vpm;

namespace {

RunConfig config(const std::string& name, std::vector<std::string> sets = {}) {
    return RunConfig::load(std::string(VPM_SOURCE_DIR) + "/configs/" + name + ".toml", sets);
}

}  // namespace

TEST(NoMapCandidate, PathTracerMissesLightOnlyWithADeltaLightAndASpecularSurface) {
    EXPECT_TRUE(path_tracer_misses_light(*config("mirror_sun_haze").scene));                  // sun and mirror
    EXPECT_FALSE(path_tracer_misses_light(*config("glass_sphere_fog").scene));                // sphere light: a path hits it
    EXPECT_TRUE(path_tracer_misses_light(*config("glass_sphere_fog", {"lights=[{type=\"point\", position=[0.0, 3.0, 0.0], intensity=[1.0, 1.0, 1.0]}]"}).scene));
    EXPECT_FALSE(path_tracer_misses_light(*config("homogeneous").scene));                     // spot light, no shapes
    EXPECT_FALSE(path_tracer_misses_light(*config("cornell_smoke").scene));                   // no mirror or glass
}

TEST(NoMapCandidate, AutoKeepsThePhotonMapWhereTheSunMeetsAMirror) {
    for (const char* seed : {"render.seed=1", "render.seed=2", "render.seed=3"}) {
        const RunConfig c = config("mirror_sun_haze", {"render.integrator=\"auto\"", "render.width=16", "render.height=16",
                                                       "render.spp=2", "photons.count=20000", seed});
        RunOptions o;
        o.progress = false;
        const RunResult r = run(c, o);
        EXPECT_EQ(r.stats.integrator_used, "photon_map") << seed;
        ASSERT_TRUE(PhotonMapStats::of(r.stats).auto_gather) << seed;
        for (const GatherMeasurement& m : PhotonMapStats::of(r.stats).auto_gather->candidates) EXPECT_NE(m.name, kNoMapCandidate) << seed;
    }
}
