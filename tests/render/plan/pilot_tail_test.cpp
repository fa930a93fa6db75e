// The auto pilot's heavy-tail figures for "continue" (render/plan/pilot_tail.h, render/plan/no_map_candidate.h):
// the share of the variance in a candidate's largest 1/1024 samples and the standard error of the
// variance read, from synthetic pilot samples (fake hooks) with a light and a heavy tail; the longer
// pilot a candidate without a map takes (the plan's charge on that figure: pass_plan_test.cpp); and a
// small render where the tail is heavy (a point-lit box at g = 0.8) and where it is not (g = 0).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/sampling/rng.h"
#include "photon/map/photon_map.h"
#include "render/plan/map_noise_pilot.h"
#include "render/plan/no_map_candidate.h"
#include "render/plan/pilot_tail.h"
#include "support/vpm_process.h"
#include "render/run/run.h"
#include "scene/camera.h"
#include "support/fake_map_pilot.h"
#include "render/photon_map/photon_map_stats.h"

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

TEST(PilotTail, RelativeStandardErrorOfTheVarianceRead) {
    // n equal squares: no spread, no error. One square in n holding everything: sqrt(1 - 1/n).
    EXPECT_DOUBLE_EQ(mean_of_squares_relative_se(std::vector<double>(16, 2.0)), 0.0);
    std::vector<double> one(16, 0.0);
    one[3] = 5.0;
    EXPECT_DOUBLE_EQ(mean_of_squares_relative_se(one), std::sqrt(1.0 - 1.0 / 16.0));
    // Two values 1 and 3: mean 2, population sd 1, so the SE of the mean of two is 1/sqrt(2)/2.
    EXPECT_NEAR(mean_of_squares_relative_se({1.0, 3.0}), std::sqrt(0.5) / 2.0, 1e-15);
    EXPECT_EQ(mean_of_squares_relative_se({}), 0.0);
    EXPECT_EQ(mean_of_squares_relative_se({0.0, 0.0}), 0.0);
}

namespace {

std::vector<GatherMeasurement> pilot(const std::function<double(Rng&)>& no_map) {
    const Camera camera(Vec3(0, 0, 4), Vec3(0, 0, 0), Vec3(0, 1, 0), 40.0, 32, 32);
    const PhotonMap map;
    test::FakeMapPilot fake(2);
    fake.no_map = no_map;
    MapNoisePilotHooks h = fake.hooks();
    const std::vector<PilotCandidate> candidates = {{"collision", true}, {"march", true}, {kNoMapCandidate, false}};
    auto m = measure_gathers(camera, map, candidates, h, 11, 0);
    return m;
}

}  // namespace

TEST(PilotTail, AHeavyTailIsReadAndChargedNotExcluded) {
    // The no-map candidate spends what the two gathers spent (8 samples x 3 maps x 40 units each):
    // 1920 of its 1-unit samples per pixel, capped at kNoMapPilotSamples.
    const auto light = pilot([](Rng& rng) { return -std::log(1.0 - rng.uniform()); });   // exponential
    EXPECT_EQ(light[0].samples, kPilotSamples);
    EXPECT_EQ(light[2].samples, kNoMapPilotSamples);
    // 64 x 1024 exponential samples: above q = ln 1024 the squared deviations (x - 1)^2 hold
    // ((q - 1)^2 + 2 (q - 1) + 2) / 1024 = 4.8% of their mean 1 (the largest 64: +-13% of that).
    EXPECT_GT(light[2].tail_share, 0.035);
    EXPECT_LT(light[2].tail_share, 0.07);
    // (x - 1)^2 of an exponential has mean 1 and mean square 9 (its fourth central moment): the
    // variance read from 65536 of them has a relative SE of sqrt(8 / 65536) = 0.011.
    EXPECT_NEAR(light[2].v_camera_rel_se, 0.011, 0.004);
    // Mostly zeros (a thin medium over few pixels): 4% exponential, the rest 0. The largest 1/1024 of
    // all samples are then the largest 2.4% of the non-zero ones: ~0.29 of the squares.
    const auto sparse = pilot([](Rng& rng) { return rng.uniform() < 0.04 ? -std::log(1.0 - rng.uniform()) : 0.0; });
    EXPECT_GT(sparse[2].tail_share, 0.15);
    EXPECT_LT(sparse[2].tail_share, 0.5);
    // The g = 0.8 continuation's shape (docs/studies/auto_plan.md section 16): exponential samples, and one in
    // 5000 worth 2000 times the mean. Its mean and variance at 8 samples per pixel (512) mostly miss it;
    // at 1024 per pixel ~13 such samples hold nearly all of the variance, read to ~1/sqrt(13) = 0.28.
    const auto heavy = pilot([](Rng& rng) { return rng.uniform() < 2e-4 ? 2000.0 : -std::log(1.0 - rng.uniform()); });
    EXPECT_GT(heavy[2].tail_share, 0.5);
    EXPECT_GT(heavy[2].v_camera_rel_se, 0.15);
    EXPECT_LT(heavy[2].v_camera_rel_se, 0.5);
    // Its paths are short (1 segment per sample), so it stays a choice whatever its tail.
    EXPECT_FALSE(light[2].excluded);
    EXPECT_FALSE(heavy[2].excluded);
}

namespace {

// The matrix's point-lit box at optical thickness 1 (docs/studies/scene_matrix.md section 11.12), 16 x 16, under the
// "auto" integrator (the one whose plan measures the path tracer).
std::string box(double g) {
    static const vpm::test::ScratchDir dir;   // one per test process, removed when it ends
    const fs::path p = dir.path / ("box_g" + std::to_string(g) + ".toml");
    std::ofstream(p) << "[render]\nwidth = 16\nheight = 16\nspp = 1\nintegrator = \"auto\"\n\n"
                        "[camera]\nposition = [0.0, 0.0, 4.0]\nlook_at = [0.0, 0.0, 0.0]\nfov = 40.0\n\n"
                        "[photons]\ncount = 20000\n\n"
                        "[[lights]]\ntype = \"point\"\nposition = [2.0, 2.0, 2.0]\nintensity = 20.0\n\n"
                        "[[media]]\ntype = \"homogeneous\"\nshape = \"box\"\nmin = [-1.0, -1.0, -1.0]\nmax = [1.0, 1.0, 1.0]\n"
                        "sigma_t_scale = 0.5\nalbedo = 0.9\ng = "
                     << g << "\n";
    return p.string();
}

const GatherMeasurement& no_map_candidate(const RunResult& r) {
    return PhotonMapStats::of(r.stats).auto_gather->candidates.back();
}

}  // namespace

TEST(PilotTail, HeavyInAPointLitBoxAtG08AndLightAtG0) {
    RunOptions o;
    o.progress = false;
    const RunResult forward = run(RunConfig::load(box(0.8)), o);
    const RunResult isotropic = run(RunConfig::load(box(0.0)), o);
    ASSERT_TRUE(PhotonMapStats::of(forward.stats).auto_gather && PhotonMapStats::of(isotropic.stats).auto_gather);
    const GatherMeasurement& f = no_map_candidate(forward);
    const GatherMeasurement& i = no_map_candidate(isotropic);
    ASSERT_EQ(f.name, kNoMapCandidate);
    EXPECT_GE(f.samples, 128);
    EXPECT_GE(i.samples, 128);
    // Measured at 32 x 32 (seeds 1, 2): a tail share of 0.96-0.98 at g = 0.8, 0.07 at g = 0.
    EXPECT_GT(f.tail_share, 0.5);
    EXPECT_LT(i.tail_share, 0.25);
    EXPECT_GT(f.v_camera_rel_se, 4.0 * i.v_camera_rel_se);
    // Charged at its upper bound the continuation still loses to the map at g = 0.8.
    EXPECT_NE(PhotonMapStats::of(forward.stats).auto_gather->chosen, kNoMapCandidate);
}
