// The early stop of the path tracer's pilot (render/plan/no_map_stop.h): the test on synthetic plan
// inputs (it fires where the continuation loses by far beyond its standard error, not where it wins,
// is close, or has no map candidate to lose to); the pilot's stages with fake hooks (it stops at the
// stage the hook says, and a pilot that never stops reads exactly what one without the test reads);
// and two renders on 1 and 2 threads: the glass bulb, where the path tracer loses by far and its
// pilot stops, and the default scene, where it wins and runs its whole pilot. Fixed seeds, counts only.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "core/sampling/rng.h"
#include "photon/map/photon_map.h"
#include "render/photon_map/photon_map_stats.h"
#include "render/plan/map_noise_pilot.h"
#include "render/plan/no_map_candidate.h"
#include "render/plan/no_map_stop.h"
#include "render/plan/pass_plan.h"
#include "render/run/run.h"
#include "render/run/run_config.h"
#include "scene/camera.h"
#include "support/fake_map_pilot.h"

using namespace vpm;

namespace {

// A map gather (variance 1, 100 units per sample, every query used) and the continuation (1 unit per
// sample), no budget and sizes fixed: the continuation's score is its variance x pixels x 1 unit.
PlanInputs two_candidates(double no_map_variance, double no_map_rel_se, double map_used = 1.0) {
    PlanInputs in;
    in.pixels = 1024.0;
    in.count = 1000;
    in.photon_cost = 10.0;
    GatherMeasurement map;
    map.name = "collision";
    map.v_camera = 1.0;
    map.sample_cost = 100.0;
    map.per_sample.queries = 1.0;
    map.per_sample.map_used = map_used;
    map.mean = 1.0;
    map.mean_se = 0.01;
    GatherMeasurement path = map;
    path.name = kNoMapCandidate;
    path.uses_map = false;
    path.v_camera = no_map_variance;
    path.v_camera_rel_se = no_map_rel_se;
    path.sample_cost = 1.0;
    path.per_sample = CountedOperations();
    in.candidates = {map, path};
    return in;
}

}  // namespace

TEST(NoMapStop, TheVariancesLowerBoundIsAPoissonLimitOnTheSamplesThatHoldIt) {
    EXPECT_EQ(variance_lower_factor(0.0), 1.0);   // no spread: exact
    // k = 100 samples' worth: (1 - 1/900 - 3/30)^3 = 0.7263, near the normal bound 1 - 3/10.
    EXPECT_NEAR(variance_lower_factor(0.1), std::pow(1.0 - 1.0 / 900.0 - 0.1, 3.0), 1e-15);
    // k = 4 (a tail held by a few samples): the normal bound 1 - 3/2 < 0; the Poisson limit 0.0985
    // (the exact 0.135% quantile of a Poisson mean seen 4 times is 0.55 of 4, so this is below it).
    EXPECT_NEAR(variance_lower_factor(0.5), std::pow(1.0 - 1.0 / 36.0 - 0.5, 3.0), 1e-15);
    EXPECT_GT(variance_lower_factor(0.5), 0.09);
    EXPECT_EQ(variance_lower_factor(1.0), 0.0);   // one sample's worth bounds nothing
    for (double r = 0.01; r < 1.0; r *= 1.5) EXPECT_GT(variance_lower_factor(r), variance_lower_factor(1.5 * r)) << r;
}

TEST(NoMapStop, FiresOnlyWhereTheContinuationLosesByFarBeyondItsStandardError) {
    const double m = 1.0 * (10.0 * 1000.0 + 1024.0 * 100.0);   // the map gather's score: V x (photons + camera pass)
    auto variance = [&](double ratio) { return ratio * m / 1024.0; };
    const double low = variance_lower_factor(0.1);   // 0.7263
    // 100x behind, read to 10%: at its lower bound still 73x behind.
    NoMapStopTest t = no_map_stop_test(two_candidates(variance(100.0), 0.1), 1);
    EXPECT_TRUE(t.stop);
    EXPECT_DOUBLE_EQ(t.best_map_score, m);
    EXPECT_NEAR(t.low_score, 100.0 * low * m, 1e-9 * m);
    // 100x behind but read to 80% (one or two samples hold its variance): bound 0.002, no stop.
    t = no_map_stop_test(two_candidates(variance(100.0), 0.8), 1);
    EXPECT_FALSE(t.stop);
    EXPECT_LT(t.low_score, 2.0 * m);
    // Close: 2.5x behind at 10% is 1.82x at its bound, under the margin of 2; 2.9x is 2.11x, over it.
    t = no_map_stop_test(two_candidates(variance(2.5), 0.1), 1);
    EXPECT_FALSE(t.stop);
    EXPECT_NEAR(t.low_score, 2.5 * low * m, 1e-9 * m);
    EXPECT_TRUE(no_map_stop_test(two_candidates(variance(2.9), 0.1), 1).stop);
    // Ahead.
    EXPECT_FALSE(no_map_stop_test(two_candidates(variance(0.5), 0.01), 1).stop);
    // A map gather that used 1% of its queries is the continuation plus a photon pass: no reference.
    t = no_map_stop_test(two_candidates(variance(100.0), 0.1, 0.01), 1);
    EXPECT_FALSE(t.stop);
    EXPECT_TRUE(std::isinf(t.best_map_score));
}

TEST(NoMapStop, AStoppedCandidateIsScoredButNotChosen) {
    const double m = 1.0 * (10.0 * 1000.0 + 1024.0 * 100.0);
    PlanInputs in = two_candidates(0.5 * m / 1024.0, 0.01);
    EXPECT_EQ(plan_passes(in).chosen, 1);   // ahead: chosen
    in.candidates[1].stopped_early = true;
    const PassPlan plan = plan_passes(in);
    EXPECT_EQ(plan.chosen, 0);
    ASSERT_EQ(plan.score.size(), 2u);
    EXPECT_LT(plan.score[1], plan.score[0]);   // its score stays in the record
}

namespace {

std::vector<GatherMeasurement> pilot(const std::function<double(Rng&)>& no_map,
                                     const std::function<bool(std::vector<GatherMeasurement>&)>& stop) {
    const Camera camera(Vec3(0, 0, 4), Vec3(0, 0, 0), Vec3(0, 1, 0), 40.0, 32, 32);
    const PhotonMap map;
    test::FakeMapPilot fake(1);
    fake.no_map = no_map;
    MapNoisePilotHooks h = fake.hooks();
    h.stop = stop;
    return measure_gathers(camera, map, {{"collision", true}, {kNoMapCandidate, false}}, h, 11, 0);
}

double exponential(Rng& rng) { return -std::log(1.0 - rng.uniform()); }

}  // namespace

TEST(NoMapStop, ThePilotStopsAtTheStageTheTestSaysAndOtherwiseReadsAsWithoutIt) {
    // The stages: 8 samples per pilot pixel, doubling; the hook sees both candidates, itself last.
    std::vector<int> stages;
    const auto stopped = pilot(exponential, [&](std::vector<GatherMeasurement>& so_far) {
        EXPECT_EQ(so_far.size(), 2u);
        EXPECT_GT(so_far.back().v_camera, 0.0);
        stages.push_back(so_far.back().samples);
        so_far.back().stop_low_score = 3.0;
        return so_far.back().samples == 32;
    });
    EXPECT_EQ(stages, (std::vector<int>{8, 16, 32}));
    EXPECT_TRUE(stopped[1].stopped_early);
    EXPECT_EQ(stopped[1].samples, 32);
    EXPECT_EQ(stopped[1].stop_low_score, 3.0);
    EXPECT_FALSE(stopped[0].stopped_early);
    // Never stopped: every figure as without the test, all kNoMapPilotSamples traced.
    const auto full = pilot(exponential, [](std::vector<GatherMeasurement>&) { return false; });
    const auto plain = pilot(exponential, nullptr);
    ASSERT_EQ(full.size(), plain.size());
    EXPECT_EQ(full[1].samples, kNoMapPilotSamples);
    EXPECT_FALSE(full[1].stopped_early);
    for (size_t c = 0; c < full.size(); ++c) {
        EXPECT_EQ(full[c].samples, plain[c].samples) << c;
        EXPECT_EQ(full[c].v_camera, plain[c].v_camera) << c;
        EXPECT_EQ(full[c].v_map_half, plain[c].v_map_half) << c;
        EXPECT_EQ(full[c].v_camera_rel_se, plain[c].v_camera_rel_se) << c;
        EXPECT_EQ(full[c].mean, plain[c].mean) << c;
        EXPECT_EQ(full[c].tail_share, plain[c].tail_share) << c;
        EXPECT_EQ(full[c].sample_cost, plain[c].sample_cost) << c;
    }
}

TEST(NoMapStop, ThePilotWithThePlansTestStopsWhereTheContinuationLosesByFar) {
    // The plan's test (no_map_stop_test) on the fake pilot: the gather reads variance 1/12 at 40 units
    // a sample; a continuation of 0.5 + 100 (x - 1), x exponential (the gather's mean, variance 1e4
    // at 1 unit) loses by ~2000x and stops at the first stage; one of 0.5 + 0.01 (u - 0.5) (variance
    // 1/120000) wins and runs its whole pilot.
    PlanInputs in;
    in.pixels = 1024.0;
    in.count = 1000;
    in.photon_cost = 1.0;
    auto plans_test = [&](std::vector<GatherMeasurement>& so_far) {
        PlanInputs test = in;
        test.candidates = so_far;
        const NoMapStopTest t = no_map_stop_test(test, so_far.size() - 1);
        so_far.back().stop_low_score = t.low_score;
        so_far.back().stop_best_map_score = t.best_map_score;
        return t.stop;
    };
    const auto loses = pilot([](Rng& rng) { return 0.5 + 100.0 * (exponential(rng) - 1.0); }, plans_test);
    EXPECT_TRUE(loses[1].stopped_early);
    EXPECT_EQ(loses[1].samples, kNoMapStopFirstStage);
    EXPECT_GT(loses[1].stop_low_score, kNoMapStopMargin * loses[1].stop_best_map_score);
    const auto wins = pilot([](Rng& rng) { return 0.5 + 0.01 * (rng.uniform() - 0.5); }, plans_test);
    EXPECT_FALSE(wins[1].stopped_early);
    EXPECT_EQ(wins[1].samples, kNoMapPilotSamples);
    EXPECT_LT(wins[1].stop_low_score, wins[1].stop_best_map_score);
    in.candidates = wins;
    EXPECT_EQ(plan_passes(in).chosen, 1);
}

namespace {

RunResult render_auto(const std::string& config, const std::vector<std::string>& sets, int threads) {
    RunOptions o;
    o.progress = false;
    std::vector<std::string> s = sets;
    s.push_back("render.integrator=\"auto\"");
    s.push_back("render.threads=" + std::to_string(threads));
    return run(RunConfig::load(std::string(VPM_SOURCE_DIR) + "/configs/" + config + ".toml", s), o);
}

// The path tracer's candidate of a run, and the same on 2 threads as on 1 (choice and stop record).
const GatherMeasurement& path_candidate_on_one_and_two_threads(const RunResult& a, const RunResult& b) {
    const AutoGatherStats &x = *PhotonMapStats::of(a.stats).auto_gather, &y = *PhotonMapStats::of(b.stats).auto_gather;
    EXPECT_EQ(x.chosen, y.chosen);
    EXPECT_EQ(a.stats.integrator_used, b.stats.integrator_used);
    const GatherMeasurement &p = x.candidates.back(), &q = y.candidates.back();
    EXPECT_EQ(p.name, kNoMapCandidate);
    EXPECT_EQ(p.stopped_early, q.stopped_early);
    EXPECT_EQ(p.samples, q.samples);
    EXPECT_EQ(p.v_camera, q.v_camera);
    EXPECT_EQ(p.stop_low_score, q.stop_low_score);
    EXPECT_EQ(p.stop_best_map_score, q.stop_best_map_score);
    EXPECT_EQ(x.score, y.score);
    return p;
}

}  // namespace

TEST(NoMapStop, AutoStopsThePathTracersPilotInTheGlassBulbAndNotWhereItWins) {
    // The lamp in a glass bulb (configs/glass_bulb_smoke.toml), 24 x 24: the path tracer's room is
    // fireflies, and its pilot stops before its 1024 samples per pixel.
    const std::vector<std::string> bulb = {"render.width=24", "render.height=24", "render.spp=1", "photons.count=20000"};
    const RunResult a = render_auto("glass_bulb_smoke", bulb, 1), b = render_auto("glass_bulb_smoke", bulb, 2);
    ASSERT_TRUE(PhotonMapStats::of(a.stats).auto_gather && PhotonMapStats::of(b.stats).auto_gather);
    const GatherMeasurement& stopped = path_candidate_on_one_and_two_threads(a, b);
    EXPECT_TRUE(stopped.stopped_early);
    EXPECT_LT(stopped.samples, kNoMapPilotSamples);
    EXPECT_GT(stopped.stop_low_score, kNoMapStopMargin * stopped.stop_best_map_score);
    EXPECT_EQ(a.stats.integrator_used, "photon_map");
    // The default scene (a thin medium lit directly), 32 x 32 under 1 s: the path tracer wins and
    // its pilot runs to its budget share, tested at every stage and never stopped.
    const std::vector<std::string> lit = {"render.width=32", "render.height=32", "render.time_limit=1"};
    const RunResult c = render_auto("default", lit, 1), d = render_auto("default", lit, 2);
    ASSERT_TRUE(PhotonMapStats::of(c.stats).auto_gather && PhotonMapStats::of(d.stats).auto_gather);
    const GatherMeasurement& full = path_candidate_on_one_and_two_threads(c, d);
    EXPECT_FALSE(full.stopped_early);
    EXPECT_GT(full.stop_best_map_score, 0.0);   // tested
    EXPECT_LT(full.stop_low_score, full.stop_best_map_score);
    EXPECT_EQ(PhotonMapStats::of(c.stats).auto_gather->chosen, kNoMapCandidate);
    EXPECT_EQ(c.stats.integrator_used, "path");
}
