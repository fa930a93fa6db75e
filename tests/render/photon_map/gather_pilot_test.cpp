// photons.gather = "pilot" (issue 20): each pass renders a pilot with the collision, march and
// auto (threshold) gathers and keeps the least variance x cost, the cost from counted work. The
// pilot uses streams of its own and puts its counters back, so it renders exactly the image of the
// gather it chose; the choice and its figures must not depend on the thread count or on the
// scene's scale, and the image stays unbiased (furnace).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "render/run/run.h"
#include "support/render_statistics.h"
#include "render/photon_map/photon_map_stats.h"

using namespace vpm;

namespace {

RunResult render(const std::string& file, const std::vector<std::string>& sets) {
    RunOptions o;
    o.progress = false;
    return run(RunConfig::load(file, sets), o);
}

const std::string kThinCube = VPM_SOURCE_DIR "/configs/thin_cube.toml";

std::vector<std::string> small(std::vector<std::string> sets) {
    std::vector<std::string> all = {"render.width=12", "render.height=12", "render.spp=2", "photons.count=5000"};
    all.insert(all.end(), sets.begin(), sets.end());
    return all;
}

// configs/thin_cube.toml with every length times s (sigma_t / s, point intensity times s^2).
std::vector<std::string> scene_scaled(double s) {
    auto v = [s](double x, double y, double z) {
        return "[" + std::to_string(x * s) + ", " + std::to_string(y * s) + ", " + std::to_string(z * s) + "]";
    };
    return {"camera.position=" + v(0.5, 0.5, 3.5), "camera.look_at=" + v(0.5, 0.5, 0.5), "lights.0.position=" + v(2.5, 2.0, 2.0),
            "lights.0.intensity=" + std::to_string(20.0 * s * s), "media.0.min=" + v(0, 0, 0), "media.0.max=" + v(1, 1, 1),
            "media.0.sigma_t_scale=" + std::to_string(1.0 / s)};
}

}  // namespace

TEST(GatherPilot, RendersExactlyTheGatherItChose) {
    const RunResult a = render(kThinCube, small({"photons.gather=\"pilot\"", "render.passes=2", "render.spp=4"}));
    ASSERT_TRUE(PhotonMapStats::of(a.stats).gather_pilot);
    const GatherPilotStats& p = *PhotonMapStats::of(a.stats).gather_pilot;
    ASSERT_EQ(p.candidates.size(), 3u);
    ASSERT_EQ(p.chosen_count.size(), 3u);
    for (size_t c = 0; c < 3; ++c) {
        EXPECT_TRUE(std::isfinite(p.variance[c]) && p.variance[c] > 0.0) << p.candidates[c];
        EXPECT_GT(p.cost[c], 0.0) << p.candidates[c];
    }
    // The march gathers at gather_queries points per segment: it costs more per sample here.
    EXPECT_GT(p.cost[1], p.cost[0]);
    const int chosen = int(std::find(p.candidates.begin(), p.candidates.end(), p.chosen) - p.candidates.begin());
    ASSERT_LT(chosen, 3);
    for (size_t c = 0; c < 3; ++c) {   // the least variance x cost (ties: the cheaper)
        EXPECT_LE(p.variance[size_t(chosen)] * p.cost[size_t(chosen)], p.variance[c] * p.cost[c]) << p.candidates[c];
    }
    ASSERT_EQ(p.chosen_count[size_t(chosen)], 2u) << "the two passes' maps chose differently: the test needs one choice";
    const RunResult f = render(kThinCube, small({"photons.gather=\"" + p.chosen + "\"", "render.passes=2", "render.spp=4"}));
    EXPECT_EQ(a.image.rgb, f.image.rgb) << "chose " << p.chosen;
    EXPECT_EQ(PhotonMapStats::of(a.stats).volume_estimates->queries, PhotonMapStats::of(f.stats).volume_estimates->queries);
    EXPECT_FALSE(PhotonMapStats::of(f.stats).gather_pilot);
}

TEST(GatherPilot, SameChoiceAndFiguresOnOneAndTwoThreads) {
    const RunResult one = render(kThinCube, small({"render.threads=1", "photons.gather=\"pilot\""}));
    const RunResult two = render(kThinCube, small({"render.threads=2", "photons.gather=\"pilot\""}));
    ASSERT_TRUE(PhotonMapStats::of(one.stats).gather_pilot && PhotonMapStats::of(two.stats).gather_pilot);
    EXPECT_EQ(PhotonMapStats::of(one.stats).gather_pilot->chosen, PhotonMapStats::of(two.stats).gather_pilot->chosen);
    EXPECT_EQ(PhotonMapStats::of(one.stats).gather_pilot->variance, PhotonMapStats::of(two.stats).gather_pilot->variance);
    EXPECT_EQ(PhotonMapStats::of(one.stats).gather_pilot->cost, PhotonMapStats::of(two.stats).gather_pilot->cost);
    EXPECT_EQ(one.image.rgb, two.image.rgb);
}

TEST(GatherPilot, SameChoiceAndFiguresAtScale1e3) {
    // Every random decision is the same up to rounding, so the figures agree closely and the
    // choice is the same. (The image itself: tests/analysis scene_matrix_test, 24a's tests.)
    std::vector<std::string> sa = scene_scaled(1.0), sb = scene_scaled(1e3);
    sa.push_back("photons.gather=\"pilot\"");
    sb.push_back("photons.gather=\"pilot\"");
    const RunResult a = render(kThinCube, small(sa));
    const RunResult b = render(kThinCube, small(sb));
    ASSERT_TRUE(PhotonMapStats::of(a.stats).gather_pilot && PhotonMapStats::of(b.stats).gather_pilot);
    EXPECT_EQ(PhotonMapStats::of(a.stats).gather_pilot->chosen, PhotonMapStats::of(b.stats).gather_pilot->chosen);
    for (size_t c = 0; c < 3; ++c) {
        EXPECT_NEAR(PhotonMapStats::of(b.stats).gather_pilot->variance[c], PhotonMapStats::of(a.stats).gather_pilot->variance[c], 0.02 * PhotonMapStats::of(a.stats).gather_pilot->variance[c]) << c;
        EXPECT_NEAR(PhotonMapStats::of(b.stats).gather_pilot->cost[c], PhotonMapStats::of(a.stats).gather_pilot->cost[c], 0.02 * PhotonMapStats::of(a.stats).gather_pilot->cost[c]) << c;
    }
}

TEST(GatherPilot, FurnaceStaysUnbiasedWithThePilotsChoice) {
    // configs/uniform_furnace.toml: radiance 0.5 everywhere, the corrected estimator unbiased.
    const RunConfig config = RunConfig::load(VPM_SOURCE_DIR "/configs/uniform_furnace.toml",
                                             {"render.width=12", "render.height=12", "render.spp=2", "photons.count=20000",
                                              "photons.gather=\"pilot\""});
    const test::Sample s = test::repeated_run_brightness(config, 40);
    std::printf("furnace, pilot's gather: %.5f +- %.5f (exact 0.5)\n", s.mean(), s.se());
    EXPECT_NEAR(s.mean(), 0.5, 3.0 * s.se());
    EXPECT_LT(s.se(), 0.01) << "too noisy to tell 3%";
    const RunResult r = render(VPM_SOURCE_DIR "/configs/uniform_furnace.toml",
                               {"render.width=12", "render.height=12", "render.spp=2", "photons.count=20000", "photons.gather=\"pilot\""});
    ASSERT_TRUE(PhotonMapStats::of(r.stats).gather_pilot);
    EXPECT_EQ(PhotonMapStats::of(r.stats).gather_pilot->chosen_count[0] + PhotonMapStats::of(r.stats).gather_pilot->chosen_count[1] + PhotonMapStats::of(r.stats).gather_pilot->chosen_count[2], 1u);
}
