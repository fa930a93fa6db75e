// photons.store_probability = "auto" (photon/trace/store_thinning.h): the rule, its effect on the photon
// pass (thins where walks store many collisions, not where they store few), unbiasedness of the
// stored power and of the furnace image, the same photons on 1 and 2 threads, and the key's
// validation.
#include <gtest/gtest.h>

#include <tbb/task_arena.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "photon/map/photon_map.h"
#include "photon/trace/store_thinning.h"
#include "photon/trace/photon_tracer.h"
#include "render/photon_map/photon_map_integrator.h"
#include "render/run/run_config.h"
#include "support/render_statistics.h"
#include "render/photon_map/photon_map_stats.h"

using namespace vpm;

namespace {

// The uniform furnace: a non-absorbing sphere of optical radius 3.6, where every walk stores a
// long chain of collisions.
RunConfig furnace(std::vector<std::string> sets = {}) {
    for (const char* s : {"render.width=16", "render.height=16", "render.spp=1"}) sets.push_back(s);
    return RunConfig::load(VPM_SOURCE_DIR "/configs/uniform_furnace.toml", sets);
}

PhotonTraceResult trace(const Scene& scene, bool automatic, uint64_t seed, uint64_t count = 100000) {
    PhotonTraceSettings s;
    s.count = count;
    s.seed = seed;
    s.progress = false;
    s.store_direct = true;
    s.store_auto = automatic;
    return trace_photons(scene, s);
}

double stored_power(const PhotonTraceResult& r) {
    double sum = 0.0;
    for (const PhotonInput& p : r.photons) sum += p.power[1];
    return sum;
}

}  // namespace

TEST(StoreThinning, RuleKeepsAboutTwoPhotonsPerWalk) {
    EXPECT_EQ(auto_store_probability(800, 100), 0.25);
    EXPECT_EQ(auto_store_probability(150, 100), 1.0);   // fewer than 2 per walk: no thinning
    EXPECT_EQ(auto_store_probability(0, 0), 1.0);
}

TEST(StoreThinning, AutoThinsLongWalksAndKeepsTheStoredPowerUnbiased) {
    // Paired by seed: the first batch (4096 photons, stored in full by both) is the same photons,
    // so the difference in stored power comes from the rest only: 4 standard errors of its mean.
    const RunConfig config = furnace();
    test::Sample diff, full;
    double q = 0.0, kept = 0.0;
    for (uint64_t seed = 1; seed <= 8; ++seed) {
        const PhotonTraceResult a = trace(*config.scene, false, seed, 200000), b = trace(*config.scene, true, seed, 200000);
        EXPECT_EQ(a.store_probability, 1.0);
        full.add(stored_power(a));
        diff.add(stored_power(b) - stored_power(a));
        q = b.store_probability;
        kept = double(b.photons.size()) / double(a.photons.size());
        EXPECT_GT(double(a.photons.size()) / double(a.storing_walks), 4.0);   // long walks: q < 1
    }
    std::printf("furnace: q = %.4f, stored %.3f of q = 1's; stored power (q = 1) %.3f, auto - (q = 1): %.3f +- %.3f\n", q,
                kept, full.mean(), diff.mean(), diff.se());
    EXPECT_LT(q, 0.5);
    EXPECT_GT(q, 0.0);
    EXPECT_LT(kept, 0.6);
    EXPECT_NEAR(diff.mean(), 0.0, 4.0 * diff.se());
}

TEST(StoreThinning, AutoKeepsEveryPhotonWhereWalksStoreFew) {
    // The thin cube (optical depth ~0.4): walks store about one photon, so q = 1 and the photons
    // are those of store_probability = 1, bit for bit.
    const RunConfig config = RunConfig::load(VPM_SOURCE_DIR "/configs/thin_cube.toml");
    const PhotonTraceResult a = trace(*config.scene, false, 5), b = trace(*config.scene, true, 5);
    EXPECT_EQ(b.store_probability, 1.0);
    ASSERT_EQ(a.photons.size(), b.photons.size());
    EXPECT_EQ(stored_power(a), stored_power(b));
}

TEST(StoreThinning, SamePhotonsOnOneAndTwoThreads) {
    const RunConfig config = furnace();
    PhotonTraceResult r[2];
    for (int t = 0; t < 2; ++t) {
        tbb::task_arena arena(t + 1);
        arena.execute([&] { r[t] = trace(*config.scene, true, 9, 200000); });
    }
    EXPECT_EQ(r[0].store_probability, r[1].store_probability);
    ASSERT_EQ(r[0].photons.size(), r[1].photons.size());
    EXPECT_EQ(stored_power(r[0]), stored_power(r[1]));
    for (size_t i = 0; i < r[0].photons.size(); i += 997) EXPECT_EQ(r[0].photons[i].position, r[1].photons[i].position);
}

TEST(StoreThinning, FurnaceStaysAtItsRadianceWithAuto) {
    // Radiance 0.5 everywhere (corrected, k = 8): the whole renderer with "auto", mean over maps.
    const RunConfig config = furnace({"photons.store_probability=\"auto\""});
    const PhotonMapSettings& ps = photon_map_settings(config);
    ASSERT_TRUE(ps.store_auto);
    test::Sample image;
    for (uint64_t r = 0; r < 10; ++r) {
        RunOptions o;
        o.progress = false;
        o.stream_offset = r;
        const RunResult res = run(config, o);
        image.add(res.image.mean());
        ASSERT_TRUE(PhotonMapStats::of(res.stats).photons.has_value());
        EXPECT_LT(PhotonMapStats::of(res.stats).photons->store_probability, 0.5);
    }
    std::printf("furnace with auto: %.4f +- %.4f (0.5)\n", image.mean(), image.se());
    EXPECT_NEAR(image.mean(), 0.5, 3.0 * image.se());
}

TEST(StoreThinning, KeyAcceptsANumberOrAutoOnly) {
    auto error_of = [](const std::string& set) {
        try {
            RunConfig::load(VPM_SOURCE_DIR "/configs/uniform_furnace.toml", {set});
        } catch (const std::exception& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    EXPECT_EQ(error_of("photons.store_probability=\"auto\""), "");
    EXPECT_EQ(error_of("photons.store_probability=0.5"), "");
    for (const char* bad : {"photons.store_probability=\"sometimes\"", "photons.store_probability=0",
                            "photons.store_probability=1.5", "photons.store_probability=true"}) {
        const std::string e = error_of(bad);
        EXPECT_NE(e.find("photons.store_probability"), std::string::npos) << bad << ": " << e;
        EXPECT_NE(e.find("\"auto\""), std::string::npos) << bad << ": " << e;
    }
}
