// render.passes and render.time_limit: independent passes (a fresh photon map each) averaged
// into one image. In the uniform furnace every pass is an independent estimate, so the mean over
// passes must stay within standard errors of 0.5 (corrected) and 0.5 k/(k-1) (classic): passes
// average away the corrected estimate's variance but not the classic estimate's bias.
#include <gtest/gtest.h>

#include <algorithm>
#include <sstream>
#include <string>

#include <tbb/task_arena.h>

#include "core/error.h"
#include "render/photon_map/photon_map_settings.h"
#include "render/run/run.h"
#include "render/run/run_stats.h"
#include "support/furnace.h"
#include "support/render_statistics.h"
#include "render/photon_map/photon_map_stats.h"

using namespace vpm;

namespace {

RunResult run_furnace(std::vector<std::string> sets) {
    for (const char* s : {"render.width=16", "render.height=16", "photons.count=40000", "photons.k=8"}) sets.push_back(s);
    RunOptions o;
    o.progress = false;
    return run(RunConfig::load(VPM_SOURCE_DIR "/configs/uniform_furnace.toml", sets), o);
}

}  // namespace

TEST(Passes, FurnaceMeanOverPassesCorrectedUnbiasedClassicHighByKOverKMinusOne) {
    const int passes = 12;
    const std::vector<std::string> sets = {"render.spp=12", "render.passes=12"};
    auto with = [&](const char* estimator) {
        std::vector<std::string> s = sets;
        s.push_back(std::string("photons.estimator=\"") + estimator + "\"");
        return run_furnace(s);
    };
    const RunResult classic = with("classic"), corrected = with("corrected");
    ASSERT_EQ(corrected.stats.passes.size(), size_t(passes));
    test::Sample c, u, excess;
    for (int p = 0; p < passes; ++p) {
        EXPECT_EQ(corrected.stats.passes[size_t(p)].spp, 1);
        c.add(classic.stats.passes[size_t(p)].image_mean);
        u.add(corrected.stats.passes[size_t(p)].image_mean);
        // Same seed: the same photon maps and camera rays, so the ratio is paired.
        excess.add(classic.stats.passes[size_t(p)].image_mean / corrected.stats.passes[size_t(p)].image_mean - 1.0);
    }
    // The image is the mean of the pass images.
    EXPECT_NEAR(corrected.image.mean(), u.mean(), 1e-6 * u.mean());
    EXPECT_EQ(corrected.stats.render.samples, uint64_t(16 * 16 * 12));
    const double k = 8.0;
    EXPECT_NEAR(u.mean(), 0.5, 3.0 * u.se());
    // Classic estimates are k/(k-1) high on the image's estimated share (support/furnace.h).
    const double excess_theory = test::furnace_estimated_share(
                                     RunConfig::load(VPM_SOURCE_DIR "/configs/uniform_furnace.toml")) / (k - 1);
    EXPECT_NEAR(c.mean(), 0.5 * (1.0 + excess_theory), 3.0 * c.se());
    EXPECT_NEAR(excess.mean(), excess_theory, 3.0 * excess.se());
    EXPECT_GT(excess.mean(), 8.0 * excess.se());
    // Each pass emitted its own photons.
    ASSERT_TRUE(PhotonMapStats::of(corrected.stats).photons.has_value());
    EXPECT_EQ(PhotonMapStats::of(corrected.stats).photons->emitted, uint64_t(40000 * passes));
    EXPECT_LT(PhotonMapStats::of(corrected.stats).photons->energy.relative_imbalance(), 1e-9);
}

TEST(Passes, DeterministicOnAnyThreadCountAndPassesDiffer) {
    const std::vector<std::string> sets = {"render.spp=3", "render.passes=3", "photons.count=5000"};
    RunResult one, two;
    tbb::task_arena(1).execute([&] { one = run_furnace(sets); });
    tbb::task_arena(2).execute([&] { two = run_furnace(sets); });
    EXPECT_EQ(one.image.rgb, two.image.rgb);
    ASSERT_EQ(one.stats.passes.size(), 3u);
    // Independent streams: the passes are not copies of each other.
    EXPECT_NE(one.stats.passes[0].image_mean, one.stats.passes[1].image_mean);
    EXPECT_NE(one.stats.passes[1].image_mean, one.stats.passes[2].image_mean);
}

TEST(Passes, OnePassIsTheClassicSingleRun) {
    // passes = 1 keeps the streams of a run without passes: a repeat offset moves the whole run.
    const RunResult a = run_furnace({"render.spp=2", "photons.count=5000"});
    const RunResult b = run_furnace({"render.spp=2", "photons.count=5000", "render.passes=1"});
    EXPECT_EQ(a.image.rgb, b.image.rgb);
    ASSERT_EQ(a.stats.passes.size(), 1u);
    EXPECT_EQ(a.stats.passes[0].spp, 2);
}

TEST(Passes, SppMustBeAMultipleOfPasses) {
    try {
        RunConfig::load(VPM_SOURCE_DIR "/configs/uniform_furnace.toml", {"render.spp=5", "render.passes=2"});
        FAIL() << "no error";
    } catch (const ConfigError& e) {
        EXPECT_NE(std::string(e.what()).find("render.passes"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("multiple"), std::string::npos) << e.what();
    }
}

TEST(Passes, TimeLimitRunsMorePassesForBothIntegrators) {
    // A 4x4, 1-spp pass takes well under a millisecond; a 1 s budget holds many of them, and the
    // minimum (render.passes) always runs. The count itself depends on the machine: only its
    // lower bounds are asserted. render.passes = 1 pins the photon map's pass at 1 sample (under a
    // limit its auto plan otherwise sizes the samples per pass from render.spp on).
    for (const char* integrator : {"path", "photon_map"}) {
        RunOptions o;
        o.progress = false;
        const RunResult r = run(RunConfig::load(VPM_SOURCE_DIR "/configs/homogeneous.toml",
                                                {"render.width=4", "render.height=4", "render.spp=1", "render.passes=1", "photons.count=200",
                                                 std::string("render.integrator=") + integrator, "render.time_limit=1"}),
                                o);
        EXPECT_GT(r.stats.pass_count(), 1u) << integrator;
        EXPECT_EQ(r.stats.render.samples, 16u * r.stats.pass_count()) << integrator;
        EXPECT_EQ(r.stats.passes.size(), std::min<size_t>(r.stats.pass_count(), RunStats::kPassRecords)) << integrator;
        const RunResult tiny = run(RunConfig::load(VPM_SOURCE_DIR "/configs/homogeneous.toml",
                                                   {"render.width=4", "render.height=4", "render.spp=2", "render.passes=2",
                                                    std::string("render.integrator=") + integrator,
                                                    "render.time_limit=1e-9", "photons.count=200"}),
                                   o);
        EXPECT_EQ(tiny.stats.passes.size(), 2u) << integrator;
    }
}

// Issue 24: the path tracer's passes go in groups of at least 65536 camera samples (run.cpp,
// render_passes). The image is exactly the mean of the same passes rendered one per run
// (render.first_pass), bit for bit, on any thread count.
TEST(Passes, PassesRenderedTogetherGiveTheImageOfPassesRenderedApart) {
    auto path_run = [](std::vector<std::string> sets) {
        for (const char* s : {"render.width=8", "render.height=6", "render.integrator=path"}) sets.push_back(s);
        RunOptions o;
        o.progress = false;
        return run(RunConfig::load(VPM_SOURCE_DIR "/configs/homogeneous.toml", sets), o);
    };
    RunResult together;
    tbb::task_arena(1).execute([&] { together = path_run({"render.spp=10", "render.passes=5"}); });
    ASSERT_EQ(together.stats.pass_count(), 5u);
    std::vector<double> sum(together.image.rgb.size(), 0.0);
    for (int p = 0; p < 5; ++p) {
        const RunResult apart = path_run({"render.spp=2", "render.first_pass=" + std::to_string(p)});
        for (size_t i = 0; i < sum.size(); ++i) sum[i] += double(apart.image.rgb[i]);
        EXPECT_NEAR(together.stats.passes[size_t(p)].image_mean, apart.image.mean(), 1e-12);
    }
    std::vector<float> mean(sum.size());
    for (size_t i = 0; i < sum.size(); ++i) mean[i] = float(sum[i] / 5.0);
    EXPECT_EQ(together.image.rgb, mean);
    const RunResult two_threads = path_run({"render.spp=10", "render.passes=5"});
    EXPECT_EQ(two_threads.image.rgb, together.image.rgb);
}

TEST(Passes, FurnaceMarchGatherCorrectedUnbiased) {
    // gather = "march" estimates the in-scattering at 4 stratified points of every camera ray,
    // each weighted by a ratio-tracked transmittance; the escaped environment is weighted by the
    // free-flight indicator. In the furnace the sum stays 0.5 for the corrected estimator.
    const int passes = 12;
    const RunResult r = run_furnace({"render.spp=12", "render.passes=12", "photons.gather=\"march\"",
                                     "photons.estimator=\"corrected\""});
    const RunResult c = run_furnace({"render.spp=12", "render.passes=12", "photons.gather=\"march\"",
                                     "photons.estimator=\"classic\""});
    test::Sample u, excess;
    for (int p = 0; p < passes; ++p) {
        u.add(r.stats.passes[size_t(p)].image_mean);
        excess.add(c.stats.passes[size_t(p)].image_mean / r.stats.passes[size_t(p)].image_mean - 1.0);
    }
    EXPECT_NEAR(u.mean(), 0.5, 3.0 * u.se());
    EXPECT_GT(excess.mean(), 8.0 * excess.se());   // the classic bias is still there
    // Every ray gathers, up to 4 queries per camera sample (fewer once ratio tracking's roulette
    // ends the transmittance); the collision estimator makes at most one.
    ASSERT_TRUE(PhotonMapStats::of(r.stats).volume_estimates.has_value());
    EXPECT_LE(PhotonMapStats::of(r.stats).volume_estimates->queries, uint64_t(16 * 16 * 12 * 4));
    EXPECT_GT(PhotonMapStats::of(r.stats).volume_estimates->queries, uint64_t(16 * 16 * 12 * 2));
}

TEST(Passes, ShrinkScheduleFollowsKnausZwickerAndStaysUnbiased) {
    PhotonMapSettings s;
    s.k = 32;
    EXPECT_EQ(s.k_for_pass(0), 32);
    EXPECT_EQ(s.k_for_pass(7), 32);   // fixed schedule
    s.schedule = KSchedule::shrink;
    s.alpha = 2.0 / 3.0;
    EXPECT_EQ(s.k_for_pass(0), 32);
    EXPECT_EQ(s.k_for_pass(7), 16);    // 32 * 8^(-1/3)
    EXPECT_EQ(s.k_for_pass(63), 8);    // 32 * 64^(-1/3)
    EXPECT_EQ(s.k_for_pass(1 << 20), 4);   // the floor
    // Every pass is unbiased for the corrected estimator, whatever its k: the furnace mean holds.
    const int passes = 12;
    const RunResult r = run_furnace({"render.spp=12", "render.passes=12", "photons.schedule=\"shrink\"",
                                     "photons.estimator=\"corrected\""});
    test::Sample u;
    for (int p = 0; p < passes; ++p) u.add(r.stats.passes[size_t(p)].image_mean);
    EXPECT_NEAR(u.mean(), 0.5, 3.0 * u.se());
    // k_floor below the estimator's minimum + 1 is refused.
    EXPECT_THROW(RunConfig::load(VPM_SOURCE_DIR "/configs/uniform_furnace.toml", {"photons.k_floor=2"}), ConfigError);
}

// Issue 47: under render.time_limit the path tracer's pass is one sample per pixel unless
// render.passes pins spp / passes, so a scene file's large spp no longer makes a first pass that
// overruns the limit (configs/cornell_smoke_path.toml at 1 s: 46.8 s before, 1.1 s now). A limit
// far below one pass writes exactly one pass: a count, not a time, is asserted.
TEST(Passes, TimeLimitedPathPassesHoldOneSampleUnlessPassesIsSet) {
    RunOptions o;
    o.progress = false;
    auto path_run = [&](std::vector<std::string> sets) {
        for (const char* s : {"render.width=5", "render.height=3", "render.integrator=path", "render.time_limit=1e-9"})
            sets.push_back(s);
        return run(RunConfig::load(VPM_SOURCE_DIR "/configs/homogeneous.toml", sets), o);
    };
    const RunResult sized = path_run({"render.spp=4096"});
    EXPECT_EQ(sized.stats.pass_count(), 1u);
    EXPECT_EQ(sized.stats.render.samples, 15u);
    ASSERT_EQ(sized.stats.passes.size(), 1u);
    EXPECT_EQ(sized.stats.passes[0].spp, 1);
    const RunResult pinned = path_run({"render.spp=64", "render.passes=4"});
    EXPECT_EQ(pinned.stats.pass_count(), 4u);   // render.passes is the minimum
    EXPECT_EQ(pinned.stats.render.samples, 15u * 64u);
    ASSERT_FALSE(pinned.stats.warnings.empty());
    EXPECT_NE(pinned.stats.warnings[0].find("shorter than the first passes"), std::string::npos) << pinned.stats.warnings[0];
    // Without a limit spp is the pass, as always.
    RunOptions untimed;
    untimed.progress = false;
    const RunResult plain = run(RunConfig::load(VPM_SOURCE_DIR "/configs/homogeneous.toml",
                                                {"render.width=5", "render.height=3", "render.integrator=path", "render.spp=8"}),
                                untimed);
    EXPECT_EQ(plain.stats.render.samples, 15u * 8u);
    EXPECT_TRUE(plain.stats.warnings.empty());
}

// A photons.count that is set is honoured under a time limit; a probe's counted work says before
// the trace when its photon pass alone cannot fit, in the log and the sidecar's warnings.
TEST(Passes, PinnedPhotonCountThatCannotFitTheLimitIsWarnedAboutOrRefused) {
    RunOptions o;
    o.progress = false;
    auto furnace = [&](const char* count, const char* limit) {
        return run(RunConfig::load(VPM_SOURCE_DIR "/configs/uniform_furnace.toml",
                                   {"render.width=4", "render.height=4", "render.spp=1", "render.passes=1",
                                    count, "photons.gather=\"collision\"", limit}),
                   o);
    };
    const RunResult tight = furnace("photons.count=20000", "render.time_limit=1e-6");
    ASSERT_FALSE(tight.stats.warnings.empty());
    EXPECT_NE(tight.stats.warnings[0].find("photons.count = 20000 is set"), std::string::npos) << tight.stats.warnings[0];
    EXPECT_EQ(PhotonMapStats::of(tight.stats).photons->emitted, 20000u);   // honoured all the same
    const RunResult roomy = furnace("photons.count=1000", "render.time_limit=0.2");   // ~1e-3 s of counted work
    for (const auto& w : roomy.stats.warnings) EXPECT_EQ(w.find("photons.count"), std::string::npos) << w;
    // Past 1.2 x limit + 1 s of one core (here ~2 s for 1e6 photons) the run is refused before the trace.
    try {
        furnace("photons.count=1000000", "render.time_limit=1e-6");
        ADD_FAILURE() << "1e6 photons at a 1e-6 s limit ran";
    } catch (const ConfigError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("photons.count = 1000000 is set"), std::string::npos) << what;
        EXPECT_NE(what.find("--unset photons.count"), std::string::npos) << what;
    }
    // A gather the plan does not size, at the default count: named as the default, with the way out.
    auto homogeneous = [&](const char* gather) {
        return run(RunConfig::load(VPM_SOURCE_DIR "/configs/homogeneous.toml",
                                   {"render.width=4", "render.height=4", "render.spp=1", "render.integrator=\"photon_map\"",
                                    gather, "render.time_limit=1e-6"}),
                   o);
    };
    const RunResult threshold = homogeneous("photons.gather=\"threshold\"");
    ASSERT_FALSE(threshold.stats.warnings.empty());
    EXPECT_NE(threshold.stats.warnings[0].find("photons.count = 100000 (its default)"), std::string::npos) << threshold.stats.warnings[0];
    EXPECT_NE(threshold.stats.warnings[0].find("set photons.count to fit"), std::string::npos) << threshold.stats.warnings[0];
    // point_beam's pass is sized from its pilots (render/photon_map/beam_pass_size.h): down to the
    // small pilot's 1,024 photons, which still do not fit 1e-6 s, and it says so.
    const RunResult beam = homogeneous("photons.gather=\"point_beam\"");
    ASSERT_FALSE(beam.stats.warnings.empty());
    EXPECT_NE(beam.stats.warnings[0].find("one point_beam pass of 1024 photons"), std::string::npos) << beam.stats.warnings[0];
}

TEST(Passes, PinnedSamplesThatCannotFitTheLimitAreWarnedAboutOrRefused) {
    // A given gather under a limit: the plan measures it and sizes the photons; render.spp pinned at
    // 64 per pass is honoured, and where its counted camera work exceeds the limit the run says so.
    RunOptions o;
    o.progress = false;
    // The homogeneous sphere, photons.count left unset.
    auto sphere = [&](const char* spp, const char* limit) {
        return run(RunConfig::load(VPM_SOURCE_DIR "/configs/homogeneous.toml",
                                   {"render.width=8", "render.height=8", spp, "render.integrator=\"photon_map\"",
                                    "photons.gather=\"collision\"", limit}),
                   o);
    };
    const RunResult tight = sphere("render.spp=64", "render.time_limit=1e-6");
    ASSERT_TRUE(PhotonMapStats::of(tight.stats).auto_gather);
    EXPECT_TRUE(PhotonMapStats::of(tight.stats).auto_gather->size_photons);
    EXPECT_FALSE(PhotonMapStats::of(tight.stats).auto_gather->size_samples);
    EXPECT_EQ(tight.stats.gather_used, "collision");
    EXPECT_EQ(tight.stats.render.samples, 64u * 64u);   // honoured all the same
    bool said = false;
    for (const auto& w : tight.stats.warnings) said = said || w.find("render.spp is set") != std::string::npos;
    EXPECT_TRUE(said);
    const RunResult roomy = sphere("render.spp=1", "render.time_limit=0.05");   // ~1e-3 s of counted camera work per pass
    for (const auto& w : roomy.stats.warnings) EXPECT_EQ(w.find("render.spp"), std::string::npos) << w;
    // Past 1.2 x limit + 1 s of one core (65536 samples per pixel: ~10 s) the run is refused after the pilot.
    try {
        sphere("render.spp=65536", "render.time_limit=1e-6");
        ADD_FAILURE() << "65536 spp at a 1e-6 s limit ran";
    } catch (const ConfigError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("render.spp is set"), std::string::npos) << what;
        EXPECT_NE(what.find("--unset render.spp"), std::string::npos) << what;
    }
}

TEST(Passes, AFirstPassProjectedPastTheLimitIsSaidWhileItRuns) {
    // A pass is never cut short; where its rows so far project past the limit, the log says so
    // during the pass (not only after it). A limit of 1e-6 s is past at any speed.
    std::ostringstream log;
    RunOptions o;
    o.progress = false;
    o.log = &log;
    const RunResult r = run(RunConfig::load(VPM_SOURCE_DIR "/configs/uniform_furnace.toml",
                                            {"render.width=4", "render.height=8", "render.spp=1", "render.passes=1",
                                             "photons.count=2000", "photons.gather=\"collision\"", "render.time_limit=1e-6"}),
                            o);
    EXPECT_EQ(r.stats.pass_count(), 1u);
    const std::string text = log.str();
    const size_t projected = text.find("this pass projects to about");
    ASSERT_NE(projected, std::string::npos) << text;
    EXPECT_EQ(text.find("this pass projects to about", projected + 1), std::string::npos) << "said once";
    EXPECT_LT(projected, text.find("is shorter than the first pass")) << text;   // before the pass ends
}

// render.crop renders only the rectangle's pixels, each with the value it has in the whole image
// (its streams do not depend on the window), and leaves the rest black.
TEST(Passes, CropRendersItsPixelsAsTheWholeImageDoesAndNothingElse) {
    const std::vector<std::string> sets = {"render.spp=2", "render.passes=2", "photons.count=5000"};
    std::vector<std::string> cropped_sets = sets;
    cropped_sets.push_back("render.crop=[3,5,11,9]");
    const RunResult whole = run_furnace(sets), cropped = run_furnace(cropped_sets);
    ASSERT_EQ(cropped.image.width, 16);
    int inside = 0;
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 16; ++x)
            for (int c = 0; c < 3; ++c) {
                const size_t i = 3 * (size_t(y) * 16 + size_t(x)) + size_t(c);
                if (x >= 3 && x < 11 && y >= 5 && y < 9) {
                    EXPECT_EQ(cropped.image.rgb[i], whole.image.rgb[i]);
                    inside += cropped.image.rgb[i] > 0.0f;
                } else {
                    EXPECT_EQ(cropped.image.rgb[i], 0.0f);
                }
            }
    EXPECT_GT(inside, 0);
    EXPECT_EQ(cropped.stats.render.samples, uint64_t(8 * 4 * 2));
    // The record's pass means are the rectangle's: their mean is the cropped pixels' mean.
    double crop_sum = 0.0;
    for (int y = 5; y < 9; ++y)
        for (int x = 3; x < 11; ++x)
            for (int c = 0; c < 3; ++c) crop_sum += cropped.image.rgb[3 * (size_t(y) * 16 + size_t(x)) + size_t(c)];
    EXPECT_NEAR(cropped.stats.pass_summary.image_mean_mean, crop_sum / (8 * 4 * 3), 1e-6 * crop_sum / 96);
}

TEST(Passes, CropOutsideTheImageIsRefusedNamingTheKey) {
    for (const char* crop : {"render.crop=[3,5,17,9]", "render.crop=[3,5,3,9]", "render.crop=[1,2,3]", "render.crop=[0.5,0,4,4]"}) {
        try {
            run_furnace({"render.spp=1", crop});
            ADD_FAILURE() << crop << " was accepted";
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find("crop"), std::string::npos) << e.what();
        }
    }
}
