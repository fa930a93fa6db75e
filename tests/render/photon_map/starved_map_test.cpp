// Issue 24, item 1: a volume photon map with fewer photons than any estimate needs (empty, thinned
// by photons.store_probability = 1e-9, or photons.count = 1) must give the path tracer's answer:
// every query takes the continue-the-path fallback (photon/estimate/bounded_radius.h). Before the fix the
// collision gather ended the path with nothing (the image equalled the path tracer at max_depth 1,
// -38%), and so did the march points with the radius bound off.
#include <gtest/gtest.h>

#include <cstdio>

#include "render/run/run.h"
#include "render/run/run_config.h"
#include "support/render_statistics.h"
#include "render/photon_map/photon_map_stats.h"

using namespace vpm;

namespace {

RunConfig sphere(const std::string& integrator, const std::vector<std::string>& extra) {
    std::vector<std::string> set = {"render.width=12", "render.height=12", "render.spp=16",
                                    "render.integrator=" + integrator};
    set.insert(set.end(), extra.begin(), extra.end());
    return RunConfig::load(VPM_SOURCE_DIR "/configs/homogeneous.toml", set);
}

}  // namespace

TEST(StarvedMap, EveryGatherGivesThePathTracersImageWhenTheMapIsEmptyOrStarved) {
    const int repeats = 6;
    const test::Sample pt = test::repeated_run_brightness(sphere("path", {}), repeats);
    struct Case {
        const char* starve;
        const char* gather;
        const char* bound;
    };
    const Case cases[] = {
        {"photons.store_probability=1e-9", "collision", "2"}, {"photons.store_probability=1e-9", "march", "2"},
        {"photons.store_probability=1e-9", "auto", "2"},      {"photons.count=1", "collision", "2"},
        {"photons.count=1", "march", "2"},                    {"photons.count=1", "auto", "2"},
        {"photons.count=1", "collision", "0"},                {"photons.count=1", "march", "0"},
    };
    for (const Case& c : cases) {
        const RunConfig config = sphere("photon_map", {c.starve, std::string("photons.gather=") + c.gather,
                                                      std::string("photons.max_radius_mfp=") + c.bound});
        const test::Sample pm = test::repeated_run_brightness(config, repeats);
        const double z = (pm.mean() - pt.mean()) / std::sqrt(pm.se() * pm.se() + pt.se() * pt.se());
        std::printf("%s, gather %s, max_radius_mfp %s: photon map %.5f +- %.5f, path tracer %.5f +- %.5f, z %.2f\n",
                    c.starve, c.gather, c.bound, pm.mean(), pm.se(), pt.mean(), pt.se(), z);
        EXPECT_LT(std::abs(z), 3.0) << c.starve << " " << c.gather << " " << c.bound;
        // Multiple scattering is ~40% of this image: 10% off is far outside the noise (SE ~0.5%).
        EXPECT_NEAR(pm.mean(), pt.mean(), 0.1 * pt.mean()) << c.starve << " " << c.gather << " " << c.bound;
    }
}

TEST(StarvedMap, AStarvedMapMakesNoQueriesAndContinuesPaths) {
    RunOptions o;
    o.progress = false;
    const RunResult r = run(sphere("photon_map", {"photons.store_probability=1e-9", "photons.gather=collision"}), o);
    ASSERT_TRUE(PhotonMapStats::of(r.stats).volume_estimates.has_value());
    EXPECT_EQ(PhotonMapStats::of(r.stats).volume_estimates->queries, 0u);
    ASSERT_TRUE(PhotonMapStats::of(r.stats).continued_paths.has_value());
    EXPECT_GT(*PhotonMapStats::of(r.stats).continued_paths, 0u);
}
