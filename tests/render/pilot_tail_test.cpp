// The auto pilot's heavy-tail rule for "continue" (render/pilot_tail.h, render/no_map_candidate.h):
// the share of the variance in a candidate's largest 1/1024 samples, from synthetic pilot samples
// (fake hooks) with a light and a heavy tail, the longer pilot a candidate without a map takes, and
// a small render where the rule must fire (a point-lit box at g = 0.8) and must not (the same at g = 0).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/rng.h"
#include "photon/photon_map.h"
#include "render/map_noise_pilot.h"
#include "render/no_map_candidate.h"
#include "render/pilot_tail.h"
#include "../support/vpm_process.h"
#include "render/run.h"
#include "scene/camera.h"

using namespace vpm;
namespace fs = std::filesystem;

TEST(PilotTail, ShareOfTheLargestSquares) {
    // Eight equal squares: the largest 1/4 (two of them) hold 1/4 of the sum.
    EXPECT_DOUBLE_EQ(largest_squares_share(std::vector<double>(8, 3.0), 0.25), 0.25);
    // ceil(0.1 x 8) = 1: the single 9 of 9 + 7 x 1 holds 9/16.
    EXPECT_DOUBLE_EQ(largest_squares_share({1, 1, 9, 1, 1, 1, 1, 1}, 0.1), 9.0 / 16.0);
    EXPECT_EQ(largest_squares_share({}, 0.5), 0.0);
    EXPECT_EQ(largest_squares_share({0.0, 0.0}, 0.5), 0.0);
    EXPECT_THROW(largest_squares_share({1.0}, 0.0), Error);
    EXPECT_THROW(largest_squares_share({1.0}, 1.5), Error);
}

namespace {

// Pilot hooks whose candidates 0 and 1 ("gathers", with a map) return light samples and cost 40
// units each, and whose candidate 2 (no map) costs 1 unit and returns `no_map(rng)`.
struct FakePilot {
    std::atomic<int64_t> work{0};
    int current = 0;
    std::function<double(Rng&)> no_map;
    MapNoisePilotHooks hooks() {
        MapNoisePilotHooks h;
        h.use = [this](int c, const PhotonMap*) { current = c; };
        h.trace = [this](const Ray&, Rng& rng) {
            work += current == 2 ? 1 : 40;
            return Rgb::Constant(current == 2 ? no_map(rng) : rng.uniform());
        };
        h.counts = [this] {
            CountedOperations c;
            c.rays = double(work.load());
            c.queries = c.map_used = c.rays;   // the gathers use the map
            return c;
        };
        h.work = [](const CountedOperations& c) { return c.rays; };
        return h;
    }
};

std::vector<GatherMeasurement> pilot(const std::function<double(Rng&)>& no_map) {
    const Camera camera(Vec3(0, 0, 4), Vec3(0, 0, 0), Vec3(0, 1, 0), 40.0, 32, 32);
    const PhotonMap map;
    FakePilot fake;
    fake.no_map = no_map;
    MapNoisePilotHooks h = fake.hooks();
    const std::vector<PilotCandidate> candidates = {{"collision", true}, {"march", true}, {kNoMapCandidate, false}};
    auto m = measure_gathers(camera, map, candidates, h, 11, 0);
    // The gathers' cheap continuation in these tests: short paths, so only the tail can exclude it.
    m[2].per_sample.rays = 1.0;
    exclude_no_map_where_the_map_is_used(m);
    return m;
}

}  // namespace

TEST(PilotTail, AHeavyTailedContinuationIsNoChoiceAndALightOneIs) {
    // The no-map candidate spends what the two gathers spent (8 samples x 3 maps x 40 units each):
    // 1920 of its 1-unit samples per pixel, capped at kNoMapPilotSamples.
    const auto light = pilot([](Rng& rng) { return -std::log(1.0 - rng.uniform()); });   // exponential
    EXPECT_EQ(light[0].samples, kPilotSamples);
    EXPECT_EQ(light[2].samples, kNoMapPilotSamples);
    // 64 x 1024 exponential samples: above q = ln 1024 the squared deviations (x - 1)^2 hold
    // ((q - 1)^2 + 2 (q - 1) + 2) / 1024 = 4.8% of their mean 1 (the largest 64: +-13% of that).
    EXPECT_GT(light[2].tail_share, 0.035);
    EXPECT_LT(light[2].tail_share, 0.07);
    EXPECT_FALSE(light[2].excluded);
    // Mostly zeros (a thin medium over few pixels): 4% exponential, the rest 0. The largest 1/1024 of
    // all samples are then the largest 2.4% of the non-zero ones: ~0.29 of the squares, still below 1/2.
    const auto sparse = pilot([](Rng& rng) { return rng.uniform() < 0.04 ? -std::log(1.0 - rng.uniform()) : 0.0; });
    EXPECT_GT(sparse[2].tail_share, 0.15);
    EXPECT_LT(sparse[2].tail_share, kNoMapMaxTailShare);
    EXPECT_FALSE(sparse[2].excluded);
    // The g = 0.8 continuation's shape (BENCHMARKS.md section 16): exponential samples, and one in
    // 5000 worth 2000 times the mean. Its mean and variance at 8 samples per pixel (512) mostly miss it.
    const auto heavy = pilot([](Rng& rng) { return rng.uniform() < 2e-4 ? 2000.0 : -std::log(1.0 - rng.uniform()); });
    EXPECT_GT(heavy[2].tail_share, kNoMapMaxTailShare);
    EXPECT_TRUE(heavy[2].excluded);
    // Where no map candidate used the map the tail does not exclude it: the gathers' samples are its own.
    std::vector<GatherMeasurement> unused = heavy;
    for (GatherMeasurement& g : unused) {
        g.per_sample.map_used = 0.0;
        g.excluded = false;
    }
    exclude_no_map_where_the_map_is_used(unused);
    EXPECT_FALSE(unused[2].excluded);
    // Too few samples for the largest 1/1024 to be more than a sample or two: no test is made.
    std::vector<GatherMeasurement> few = heavy;
    few[2].excluded = false;
    few[2].samples = kNoMapTailMinSamples - 1;
    exclude_no_map_where_the_map_is_used(few);
    EXPECT_FALSE(few[2].excluded);
}

namespace {

// The matrix's point-lit box at optical thickness 1 (BENCHMARKS.md section 11.12), 16 x 16.
std::string box(double g) {
    static const vpm::test::ScratchDir dir;   // one per test process, removed when it ends
    const fs::path p = dir.path / ("box_g" + std::to_string(g) + ".toml");
    std::ofstream(p) << "[render]\nwidth = 16\nheight = 16\nspp = 1\nintegrator = \"photon_map\"\n\n"
                        "[camera]\nposition = [0.0, 0.0, 4.0]\nlook_at = [0.0, 0.0, 0.0]\nfov = 40.0\n\n"
                        "[photons]\ncount = 20000\n\n"
                        "[[lights]]\ntype = \"point\"\nposition = [2.0, 2.0, 2.0]\nintensity = 20.0\n\n"
                        "[[media]]\ntype = \"homogeneous\"\nshape = \"box\"\nmin = [-1.0, -1.0, -1.0]\nmax = [1.0, 1.0, 1.0]\n"
                        "sigma_t_scale = 0.5\nalbedo = 0.9\ng = "
                     << g << "\n";
    return p.string();
}

const GatherMeasurement& no_map_candidate(const RunResult& r) {
    return r.stats.auto_gather->candidates.back();
}

}  // namespace

TEST(PilotTail, FiresInAPointLitBoxAtG08AndNotAtG0) {
    RunOptions o;
    o.progress = false;
    const RunResult forward = run(RunConfig::load(box(0.8)), o);
    const RunResult isotropic = run(RunConfig::load(box(0.0)), o);
    ASSERT_TRUE(forward.stats.auto_gather && isotropic.stats.auto_gather);
    const GatherMeasurement& f = no_map_candidate(forward);
    const GatherMeasurement& i = no_map_candidate(isotropic);
    ASSERT_EQ(f.name, kNoMapCandidate);
    std::printf("continue: g 0.8: %d samples per pixel, tail share %.3f; g 0: %d, %.3f\n", f.samples, f.tail_share, i.samples,
                i.tail_share);
    EXPECT_GE(f.samples, kNoMapTailMinSamples);
    EXPECT_GE(i.samples, kNoMapTailMinSamples);
    // Measured at 32 x 32 (seeds 1, 2): 0.96-0.98 at g = 0.8, 0.07 at g = 0.
    EXPECT_GT(f.tail_share, kNoMapMaxTailShare);
    EXPECT_LT(i.tail_share, 0.25);
    EXPECT_TRUE(f.excluded);
    EXPECT_NE(forward.stats.auto_gather->chosen, kNoMapCandidate);
}
