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
    EXPECT_TRUE(path_tracer_misses_light(*config("plume_glass_prism").scene));                // spot and glass prism
    EXPECT_FALSE(path_tracer_misses_light(*config("mirror_ball_haze").scene));                // quad lamp: a path hits it
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

TEST(NoMapCandidate, AutoKeepsThePhotonMapUnderATimeLimitWhereASpotShinesThroughGlass) {
    // The prism's floor caustic and the light it bends into the plume: under render.time_limit the
    // pilot also sizes the passes, and still offers no path tracer (the run record says so: the
    // photon map ran, "continue" was not measured). Counts only: the same plan on 1 and 2 threads.
    std::vector<AutoGatherStats> plans;
    for (const char* threads : {"render.threads=1", "render.threads=2"}) {
        const RunConfig c = config("plume_glass_prism", {"render.integrator=\"auto\"", "render.width=24", "render.height=24",
                                                         "render.time_limit=0.5", "render.passes=1",
                                                         "photons.count=20000", "render.spp=2", threads});
        RunOptions o;
        o.progress = false;
        const RunResult r = run(c, o);
        EXPECT_EQ(r.stats.integrator_used, "photon_map");
        ASSERT_TRUE(PhotonMapStats::of(r.stats).auto_gather);
        const AutoGatherStats& a = *PhotonMapStats::of(r.stats).auto_gather;
        for (const GatherMeasurement& m : a.candidates) EXPECT_NE(m.name, kNoMapCandidate);
        EXPECT_TRUE(a.photon_pass);
        plans.push_back(a);
    }
    EXPECT_EQ(plans[0].chosen, plans[1].chosen);
    EXPECT_EQ(plans[0].count, plans[1].count);
    EXPECT_EQ(plans[0].spp, plans[1].spp);
}
