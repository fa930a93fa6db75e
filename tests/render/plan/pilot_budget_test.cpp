// The auto pilot's counted-cost bound (render/plan/pilot_budget.h, render/plan/map_noise_pilot.h): with fake
// hooks whose counted work per sample is fixed per candidate, each candidate takes the samples its
// share pays for (at least 2, at most 8), a candidate whose one-sample pass exceeds the cap stops
// after its probe once a cheaper one fitted, and without a budget every gather takes 8 (a candidate
// without a map up to kNoMapPilotSamples, within what the gathers spent).
#include <gtest/gtest.h>

#include <atomic>

#include "photon/map/photon_map.h"
#include "render/plan/map_noise_pilot.h"
#include "scene/camera.h"

using namespace vpm;

namespace {

struct FakeRun {
    std::atomic<int64_t> rays{0};
    int current = 0;
    std::vector<double> rays_per_sample;   // per candidate
    bool uses_map = true;                  // whether the traces count map estimates (else the halves are skipped)
    MapNoisePilotHooks hooks() {
        MapNoisePilotHooks h;
        h.use = [this](int c, const PhotonMap*) { current = c; };
        h.trace = [this](const Ray&, Rng& rng) {
            rays += int64_t(rays_per_sample[size_t(current)]);
            return Rgb::Constant(rng.uniform());
        };
        h.counts = [this] {
            CountedOperations c;
            c.rays = double(rays.load());
            c.map_used = uses_map ? c.rays : 0.0;
            return c;
        };
        h.work = [](const CountedOperations& c) { return c.rays; };
        return h;
    }
};

}  // namespace

TEST(PilotBudget, SamplesFollowTheShareAndDearCandidatesStopAfterTheirProbe) {
    const Camera camera(Vec3(0, 0, 4), Vec3(0, 0, 0), Vec3(0, 1, 0), 40.0, 32, 32);
    const PhotonMap map;
    const std::vector<PilotCandidate> candidates = {{"cheap", true}, {"dear", true}, {"no map", false}};
    FakeRun run;
    run.rays_per_sample = {1.0, 1000.0, 10.0};
    constexpr int kPixels = kPilotSide * kPilotSide;
    PilotBudget budget;
    budget.per_candidate = 5.0 * kPixels * 3.0;       // the cheap candidate's 5 samples with 3 maps
    budget.max_pass_cost = 100.0 * 32 * 32;           // a one-sample pass of the dear one is 1000 x pixels
    MapNoisePilotHooks h = run.hooks();
    const auto m = measure_gathers(camera, map, candidates, h, 7, 0, budget, 32.0 * 32.0);
    ASSERT_EQ(m.size(), 3u);
    EXPECT_EQ(m[0].samples, 5);
    EXPECT_FALSE(m[0].dropped);
    EXPECT_DOUBLE_EQ(m[0].sample_cost, 1.0);
    EXPECT_TRUE(m[1].dropped);
    EXPECT_EQ(m[1].samples, 1);
    EXPECT_DOUBLE_EQ(m[1].sample_cost, 1000.0);
    // One map: 5 * 64 * 3 / (64 * 10) = 1.5 samples, raised to the 2 a variance needs.
    EXPECT_EQ(m[2].samples, 2);
    EXPECT_FALSE(m[2].uses_map);
    EXPECT_EQ(m[2].v_map_half, 0.0);
    EXPECT_GT(m[2].v_camera, 0.0);
    // Counted work: the cheap candidate's 5 samples x 3 maps and its spread samples with the 3 maps, the dear
    // one's probe, the last one's 2 x 1 map.
    constexpr int kSpread = kPilotSpreadSide * kPilotSpreadSide * kPilotSpreadSamples;
    EXPECT_EQ(run.rays.load(), int64_t(5 * 3 * kPixels * 1 + 3 * kSpread * 1 + kPixels * 1000 + 2 * kPixels * 10));

    // No map estimate used: the halves are neither built nor traced (V_map and bias^2 exactly 0),
    // while the samples stay those the three-map share pays for.
    FakeRun unused;
    unused.rays_per_sample = run.rays_per_sample;
    unused.uses_map = false;
    MapNoisePilotHooks n = unused.hooks();
    const auto skipped = measure_gathers(camera, map, candidates, n, 7, 0, budget, 32.0 * 32.0);
    EXPECT_EQ(skipped[0].samples, 5);
    EXPECT_EQ(skipped[0].v_map_half, 0.0);
    EXPECT_EQ(skipped[0].bias2, 0.0);
    EXPECT_EQ(unused.rays.load(), int64_t(5 * kPixels * 1 + kSpread * 1 + kPixels * 1000 + 2 * kPixels * 10));

    FakeRun unbounded;
    unbounded.rays_per_sample = run.rays_per_sample;
    MapNoisePilotHooks u = unbounded.hooks();
    const auto all = measure_gathers(camera, map, candidates, u, 7, 0);
    for (const auto& g : all) {
        // Without a map a candidate takes what the others spent, up to kNoMapPilotSamples (here
        // (8 x 3 x 1 + 8 x 3 x 1000) / 10 per pixel: the cap).
        EXPECT_EQ(g.samples, g.uses_map ? kPilotSamples : kNoMapPilotSamples) << g.name;
        EXPECT_FALSE(g.dropped) << g.name;
    }
    EXPECT_EQ(pilot_samples(0.0, 5.0, kPixels, 3, kPilotSamples), kPilotSamples);
    EXPECT_EQ(pilot_samples(1e12, 5.0, kPixels, 3, kPilotSamples), kPilotSamples);
}
