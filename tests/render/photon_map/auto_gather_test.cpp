// photons.gather = "auto" (issue 20): the map-noise pilot (render/plan/map_noise_pilot.h) measures the
// collision and march gathers with the pass's map and its independent halves and quarters, and
// the plan (render/plan/pass_plan.h) picks the gather and, under render.time_limit with photons.count
// and render.spp not given, the photons and samples per pass. render.integrator = "photon_map"
// always renders with its map; "auto" (issue 41) also measures the path tracer ("continue") and may
// render with it. The choices come from counts and fixed streams: the same on 1 and 2 threads and
// at scale 1e3, and the image stays unbiased.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "config/params.h"
#include "core/error.h"
#include "render/photon_map/photon_map_integrator.h"
#include "render/photon_map/photon_pass.h"
#include "render/run/run.h"
#include "render/run/run_stats.h"
#include "support/render_statistics.h"
#include "support/vpm_process.h"
#include "render/photon_map/photon_map_stats.h"

using namespace vpm;
namespace fs = std::filesystem;

namespace {

// configs/thin_cube.toml without spp and count (so that a time limit sizes them), every length times s.
std::string thin_cube(double s, double sigma_t = 1.0, double albedo = 0.8) {
    auto v = [s](double x, double y, double z) {
        std::ostringstream o;
        o.precision(17);
        o << "[" << x * s << ", " << y * s << ", " << z * s << "]";
        return o.str();
    };
    std::ostringstream t;
    t.precision(17);
    t << "[render]\nwidth = 12\nheight = 12\nintegrator = \"photon_map\"\n\n"
      << "[camera]\nposition = " << v(0.5, 0.5, 3.5) << "\nlook_at = " << v(0.5, 0.5, 0.5) << "\nfov = 35\n\n"
      << "[photons]\nk = 32\n\n"
      << "[[lights]]\ntype = \"point\"\nposition = " << v(2.5, 2.0, 2.0) << "\nintensity = " << 20.0 * s * s << "\n\n"
      << "[[media]]\ntype = \"homogeneous\"\nshape = \"box\"\nmin = " << v(0, 0, 0) << "\nmax = " << v(1, 1, 1)
      << "\nsigma_t_scale = " << sigma_t / s << "\nalbedo = " << albedo << "\n";
    return t.str();
}

// Scene files go to one folder per test process (ctest runs the tests as parallel processes, and
// two suites may run at once), removed when the process ends.
std::string write(const std::string& name, const std::string& text) {
    static const vpm::test::ScratchDir dir;
    const fs::path p = dir.path / name;
    std::ofstream(p) << text;
    return p.string();
}

RunResult render(const std::string& file, const std::vector<std::string>& sets, std::ostream* log = nullptr) {
    RunOptions o;
    o.progress = false;
    o.log = log;
    return run(RunConfig::load(file, sets), o);
}

}  // namespace

TEST(AutoGather, SizesPassesOnlyUnderATimeLimitAndHonoursGivenSizes) {
    const std::string f = write("cube.toml", thin_cube(1.0));
    // One pass (a limit far below it): pass 0 is the pilot's, the plan's samples per pass apply.
    const RunResult a = render(f, {"render.time_limit=1e-9", "photons.count=20000"});
    ASSERT_TRUE(PhotonMapStats::of(a.stats).auto_gather);
    EXPECT_FALSE(PhotonMapStats::of(a.stats).auto_gather->size_photons);   // count given
    EXPECT_TRUE(PhotonMapStats::of(a.stats).auto_gather->size_samples);
    EXPECT_EQ(a.stats.pass_count(), 1u);
    EXPECT_EQ(a.stats.render.samples, 144u * uint64_t(PhotonMapStats::of(a.stats).auto_gather->spp));
    ASSERT_EQ(PhotonMapStats::of(a.stats).auto_gather->candidates.size(), 2u);   // collision, march: the photon map never goes without its map
    for (const auto& c : PhotonMapStats::of(a.stats).auto_gather->candidates) {
        EXPECT_GT(c.v_camera, 0.0) << c.name;
        EXPECT_GT(c.sample_cost, 0.0) << c.name;
        EXPECT_EQ(c.v_map_quarter, -1.0) << c.name;   // quarters only when the count is sized
    }
    // render.spp pins the samples per pass under a limit too (spp / passes), as render.passes does.
    const RunResult spp_given = render(f, {"render.time_limit=1e-9", "render.spp=3", "photons.count=20000"});
    ASSERT_TRUE(PhotonMapStats::of(spp_given.stats).auto_gather);
    EXPECT_FALSE(PhotonMapStats::of(spp_given.stats).auto_gather->size_samples);
    EXPECT_EQ(spp_given.stats.render.samples, 144u * 3u);
    // The "auto" integrator measures the path tracer too.
    const RunResult with_path = render(f, {"render.time_limit=1e-9", "photons.count=20000", "render.integrator=\"auto\""});
    ASSERT_TRUE(PhotonMapStats::of(with_path.stats).auto_gather);
    ASSERT_EQ(PhotonMapStats::of(with_path.stats).auto_gather->candidates.size(), 3u);   // collision, march, continue
    EXPECT_FALSE(PhotonMapStats::of(with_path.stats).auto_gather->candidates[2].uses_map);
    const RunResult given = render(f, {"render.time_limit=1e-9", "render.spp=3", "render.passes=1", "photons.count=20000"});
    ASSERT_TRUE(PhotonMapStats::of(given.stats).auto_gather);
    EXPECT_FALSE(PhotonMapStats::of(given.stats).auto_gather->size_samples);
    EXPECT_EQ(given.stats.render.samples, 144u * 3u);
    // photons.gather given: that gather in every pass, named in the stats. Under the limit the plan
    // measures it alone and sizes what is left unset (here the samples); with every size given, no plan.
    for (const char* g : {"collision", "march"}) {
        const std::string gather = std::string("photons.gather=\"") + g + "\"";
        const RunResult sized = render(f, {"render.time_limit=1e-9", "photons.count=20000", gather});
        ASSERT_TRUE(PhotonMapStats::of(sized.stats).auto_gather);
        EXPECT_EQ(PhotonMapStats::of(sized.stats).auto_gather->candidates.size(), 1u);
        EXPECT_FALSE(PhotonMapStats::of(sized.stats).auto_gather->size_photons);
        EXPECT_TRUE(PhotonMapStats::of(sized.stats).auto_gather->size_samples);
        EXPECT_EQ(sized.stats.render.samples, 144u * uint64_t(PhotonMapStats::of(sized.stats).auto_gather->spp) * sized.stats.pass_count());
        const RunResult pinned = render(f, {"render.time_limit=1e-9", "photons.count=20000", "render.spp=2", gather});
        EXPECT_FALSE(PhotonMapStats::of(pinned.stats).auto_gather);
        for (const RunResult* r : {&sized, &pinned}) {
            EXPECT_EQ(r->stats.gather_used, g);
            EXPECT_EQ(r->stats.integrator_used, "photon_map");
            EXPECT_EQ(PhotonMapStats::of(r->stats).photons->emitted, 20000u * r->stats.pass_count());
        }
    }
    // Where the plan keeps the count the pilot's map is pass 0's: nothing is traced for the pilot alone
    // (only the probe that checks whether the pinned count fits the limit; here it does not, and says so).
    ASSERT_TRUE(PhotonMapStats::of(a.stats).photon_ledger);
    EXPECT_EQ(PhotonMapStats::of(a.stats).photon_ledger->pilot_only, 0u);
    EXPECT_EQ(PhotonMapStats::of(a.stats).photon_ledger->probe, uint64_t(kPilotProbePhotons));
    ASSERT_EQ(a.stats.warnings.size(), 2u);   // and the limit shorter than the first pass
    EXPECT_NE(a.stats.warnings[0].find("photons.count = 20000 is set"), std::string::npos) << a.stats.warnings[0];
    EXPECT_EQ(PhotonMapStats::of(a.stats).photon_ledger->pass_maps, 20000u * a.stats.pass_count());
    EXPECT_EQ(PhotonMapStats::of(a.stats).photon_ledger->estimates, *a.stats.map_estimates);
    const RunResult no_limit = render(f, {"photons.count=20000"});
    ASSERT_TRUE(PhotonMapStats::of(no_limit.stats).auto_gather);
    EXPECT_FALSE(PhotonMapStats::of(no_limit.stats).auto_gather->size_photons || PhotonMapStats::of(no_limit.stats).auto_gather->size_samples);
    EXPECT_EQ(no_limit.stats.render.samples, 144u * 16u);   // (its gather may differ: chosen at 16 samples per pass)
}

TEST(AutoGather, PassZeroIsTracedAgainAtThePlannedCount) {
    // Under a limit that buys more photons than photons.count, pass 0 renders with a map of the
    // plan's size, not the pilot's: the run emits the pilot's 100000 and then the planned count in
    // every pass, pass 0 included (whatever number of passes the clock allows).
    // The thin cube (optical thickness 0.3, albedo 0.9) at k = 128, 64 x 64: its map noise, not a
    // bias, buys photons (the pilot's bias is charged only where resolved, render/plan/pilot_bias.h), and
    // the march with the map beats the continued paths there (at k = 32 the plan keeps 100000).
    std::ostringstream log;
    const std::string f = write("cube128.toml", thin_cube(1.0, 0.3, 0.9));
    const RunResult r = render(f, {"render.width=64", "render.height=64", "render.time_limit=4", "photons.k=128"}, &log);
    ASSERT_TRUE(PhotonMapStats::of(r.stats).auto_gather && PhotonMapStats::of(r.stats).photons);
    const AutoGatherStats& a = *PhotonMapStats::of(r.stats).auto_gather;
    ASSERT_TRUE(a.photon_pass) << log.str();
    ASSERT_GT(a.count, 100000) << log.str();   // the plan's figure: counts only, the same on any machine
    EXPECT_EQ(PhotonMapStats::of(r.stats).photons->emitted, uint64_t(100000 + a.count * int64_t(r.stats.pass_count()))) << log.str();
    EXPECT_NE(log.str().find("photons: pass 0 traced again with the plan's"), std::string::npos) << log.str();
    // The ledger names the pilot's map as the pilot's alone, the rest as the passes' maps.
    ASSERT_TRUE(PhotonMapStats::of(r.stats).photon_ledger);
    EXPECT_EQ(PhotonMapStats::of(r.stats).photon_ledger->pilot_only, 100000u);
    EXPECT_EQ(PhotonMapStats::of(r.stats).photon_ledger->pass_maps, uint64_t(a.count) * r.stats.pass_count());
    EXPECT_EQ(PhotonMapStats::of(r.stats).photon_ledger->passes_traced, int64_t(r.stats.pass_count()));
    EXPECT_NE(log.str().find("photons traced per phase: "), std::string::npos) << log.str();
}

TEST(AutoGather, ThePilotMapIsSmallerWhereWalksStoreManyPhotons) {
    // The cube at optical thickness 100, albedo 0.99 stores about 13 photons per emitted one: the
    // pilot's map holds about kPilotStoredPhotons, not 1.3 M (render/photon_map/photon_pass.h). Its count comes
    // from a probe (counts only): the same on one and two threads and for a run starting at pass 1.
    const std::string dense = write("cube100.toml", thin_cube(1.0, 100.0, 0.99));
    const std::vector<std::string> one_pass = {"render.time_limit=1e-9"};
    std::ostringstream log;
    const RunResult a = render(dense, one_pass, &log);
    ASSERT_TRUE(PhotonMapStats::of(a.stats).auto_gather && PhotonMapStats::of(a.stats).photons);
    const int64_t pilot = PhotonMapStats::of(a.stats).auto_gather->pilot_count;
    EXPECT_LT(pilot, 100000);
    EXPECT_GE(pilot, kPilotProbePhotons);
    EXPECT_EQ(pilot % kPilotProbePhotons, 0);
    EXPECT_NE(log.str().find("photons: the pilot's map of " + std::to_string(pilot) + " photons"), std::string::npos) << log.str();
    // Pass 0's first photon pass is the pilot's map; a plan that keeps the map traces pass 0 again,
    // at photons.count or more (render/plan/pass_plan.h).
    const AutoGatherStats& plan = *PhotonMapStats::of(a.stats).auto_gather;
    ASSERT_TRUE(plan.photon_pass);   // the photon-map integrator keeps its map
    EXPECT_EQ(PhotonMapStats::of(a.stats).photons->emitted, uint64_t(pilot + plan.count)) << plan.chosen;
    EXPECT_GE(plan.count, 100000);
    // The pilot map's stored photons (its "trace:" line), the probe's projection within a batch's
    // worth and the probe's noise.
    const std::string text = log.str();
    const size_t line = text.find("trace: " + std::to_string(pilot) + " photon paths, ");
    ASSERT_NE(line, std::string::npos) << text;
    const size_t collisions = text.find("collisions, ", line);
    ASSERT_NE(collisions, std::string::npos);
    const double stored = std::stod(text.substr(collisions + 12));
    EXPECT_GT(stored, 0.7 * kPilotStoredPhotons);
    EXPECT_LT(stored, 1.3 * kPilotStoredPhotons + 20.0 * double(kPilotProbePhotons));
    // Under the "auto" integrator (whose plan drops the map here, so that the runs stay short) the
    // pilot's map is the same, and so is the plan, on 1 and 2 threads and from pass 1.
    std::vector<std::string> one = one_pass, two = one_pass, later = one_pass;
    one.push_back("render.threads=1");
    two.push_back("render.threads=2");
    later.push_back("render.first_pass=1");
    std::string chosen;
    for (auto sets : {one, two, later}) {
        sets.push_back("render.integrator=\"auto\"");
        const RunResult b = render(dense, sets);
        ASSERT_TRUE(PhotonMapStats::of(b.stats).auto_gather);
        EXPECT_EQ(PhotonMapStats::of(b.stats).auto_gather->pilot_count, pilot);
        if (chosen.empty()) chosen = PhotonMapStats::of(b.stats).auto_gather->chosen;
        EXPECT_EQ(PhotonMapStats::of(b.stats).auto_gather->chosen, chosen);
    }
    // Where walks store fewer (the thin cube), or where photons.count is given, the pilot's map has photons.count.
    // (Where it has fewer the plan still sizes from photons.count up: render/plan/pass_plan.h.)
    const RunResult thin = render(write("cube.toml", thin_cube(1.0)), one_pass);
    ASSERT_TRUE(PhotonMapStats::of(thin.stats).auto_gather);
    EXPECT_EQ(PhotonMapStats::of(thin.stats).auto_gather->pilot_count, 100000);
    // (50000: 1e5 given photons in this cube count 1.2 s of one core, past 1.2 x limit + 1 s, and are refused.)
    const RunResult given = render(dense, {"render.time_limit=1e-9", "photons.count=50000"});
    ASSERT_TRUE(PhotonMapStats::of(given.stats).auto_gather);
    EXPECT_EQ(PhotonMapStats::of(given.stats).auto_gather->pilot_count, 50000);
}

TEST(AutoGather, ATimeLimitShorterThanOnePassWritesOneAndSaysSo) {
    std::ostringstream log;
    const RunResult r = render(write("cube.toml", thin_cube(1.0)), {"render.time_limit=1e-9", "photons.count=20000"}, &log);
    EXPECT_EQ(r.stats.pass_count(), 1u);
    EXPECT_EQ(r.image.width, 12);
    EXPECT_NE(log.str().find("warning: render.time_limit = 1e-09 s is shorter than the first pass"), std::string::npos) << log.str();
    EXPECT_NE(log.str().find("gather: auto chose"), std::string::npos) << log.str();
}

TEST(AutoGather, ARunFromALaterPassPlansAsPassZeroOverASurface) {
    // The pilot of a run starting at pass 1 traces pass 0's maps apart, its surface map included:
    // without it the cube over a floor planned the collision gather from pass 1 and the march from
    // pass 0 (vpm merge then lost the one-machine image).
    const std::string f = write("cube_floor.toml", thin_cube(1.0) +
                                                       "\n[[shapes]]\ntype = \"quad\"\ncenter = [0.5, -0.2, 0.5]\n"
                                                       "u = [2.0, 0.0, 0.0]\nv = [0.0, 0.0, 2.0]\nreflectance = 0.5\n");
    const RunResult zero = render(f, {"render.time_limit=1e-9", "render.width=32", "render.height=32"});
    const RunResult one = render(f, {"render.time_limit=1e-9", "render.width=32", "render.height=32", "render.first_pass=1"});
    ASSERT_TRUE(PhotonMapStats::of(zero.stats).auto_gather && PhotonMapStats::of(one.stats).auto_gather);
    const AutoGatherStats &a = *PhotonMapStats::of(zero.stats).auto_gather, &b = *PhotonMapStats::of(one.stats).auto_gather;
    EXPECT_EQ(a.chosen, b.chosen);
    EXPECT_EQ(a.count, b.count);
    EXPECT_EQ(a.spp, b.spp);
    ASSERT_EQ(a.candidates.size(), b.candidates.size());
    for (size_t c = 0; c < a.candidates.size(); ++c) {
        EXPECT_EQ(a.candidates[c].v_camera, b.candidates[c].v_camera) << a.candidates[c].name;
        EXPECT_EQ(a.candidates[c].sample_cost, b.candidates[c].sample_cost) << a.candidates[c].name;
    }
}

class AutoGatherIntegrators : public ::testing::TestWithParam<const char*> {};
INSTANTIATE_TEST_SUITE_P(PhotonMapAndAuto, AutoGatherIntegrators, ::testing::Values("photon_map", "auto"));

TEST_P(AutoGatherIntegrators, SamePlanAndImageOnOneAndTwoThreads) {
    const std::string f = write("cube.toml", thin_cube(1.0));
    // render.first_pass = 1: the pilot map is pass 0's, traced apart, and the pass uses the planned count.
    const std::vector<std::string> sets = {"render.time_limit=1e-9", "render.first_pass=1",
                                           std::string("render.integrator=\"") + GetParam() + "\""};
    std::vector<std::string> one = sets, two = sets;
    one.push_back("render.threads=1");
    two.push_back("render.threads=2");
    const RunResult a = render(f, one), b = render(f, two);
    ASSERT_TRUE(PhotonMapStats::of(a.stats).auto_gather && PhotonMapStats::of(b.stats).auto_gather);
    const AutoGatherStats &x = *PhotonMapStats::of(a.stats).auto_gather, &y = *PhotonMapStats::of(b.stats).auto_gather;
    EXPECT_TRUE(x.size_photons && x.size_samples);
    EXPECT_EQ(x.chosen, y.chosen);
    EXPECT_EQ(x.count, y.count);
    EXPECT_EQ(x.spp, y.spp);
    EXPECT_EQ(x.photon_cost, y.photon_cost);
    for (size_t c = 0; c < x.candidates.size(); ++c) {
        EXPECT_EQ(x.candidates[c].v_camera, y.candidates[c].v_camera);
        EXPECT_EQ(x.candidates[c].v_map_half, y.candidates[c].v_map_half);
        EXPECT_EQ(x.candidates[c].v_map_quarter, y.candidates[c].v_map_quarter);
        EXPECT_EQ(x.candidates[c].sample_cost, y.candidates[c].sample_cost);
    }
    EXPECT_EQ(a.stats.integrator_used, b.stats.integrator_used);
    if (x.photon_pass) {
        ASSERT_TRUE(PhotonMapStats::of(a.stats).photons);
        EXPECT_EQ(PhotonMapStats::of(a.stats).photons->emitted, uint64_t(x.count));   // pass 1 emits the planned count
        EXPECT_EQ(a.stats.integrator_used, "photon_map");
    } else {   // "continue" ("auto" only; the thin cube at this budget): pass 1 traces no photons
        EXPECT_STREQ(GetParam(), "auto");
        EXPECT_TRUE(!PhotonMapStats::of(a.stats).photons || PhotonMapStats::of(a.stats).photons->emitted == 0);
        EXPECT_EQ(a.stats.integrator_used, "path");
    }
    EXPECT_EQ(a.image.rgb, b.image.rgb);
}

TEST_P(AutoGatherIntegrators, SameChoicesAtScale1e3) {
    const std::vector<std::string> sets = {"render.time_limit=1e-9", std::string("render.integrator=\"") + GetParam() + "\""};
    const RunResult a = render(write("cube1.toml", thin_cube(1.0)), sets);
    const RunResult b = render(write("cube1e3.toml", thin_cube(1e3)), sets);
    ASSERT_TRUE(PhotonMapStats::of(a.stats).auto_gather && PhotonMapStats::of(b.stats).auto_gather);
    const AutoGatherStats &x = *PhotonMapStats::of(a.stats).auto_gather, &y = *PhotonMapStats::of(b.stats).auto_gather;
    EXPECT_EQ(x.chosen, y.chosen);
    EXPECT_EQ(a.stats.integrator_used, b.stats.integrator_used);
    EXPECT_EQ(x.count, y.count);
    EXPECT_EQ(x.spp, y.spp);
    EXPECT_NEAR(y.photon_cost, x.photon_cost, 0.01 * x.photon_cost);
    for (size_t c = 0; c < x.candidates.size(); ++c) {
        EXPECT_NEAR(y.candidates[c].v_camera, x.candidates[c].v_camera, 0.02 * x.candidates[c].v_camera) << c;
        EXPECT_NEAR(y.candidates[c].sample_cost, x.candidates[c].sample_cost, 0.02 * x.candidates[c].sample_cost) << c;
    }
}

TEST(AutoGather, FurnaceStaysUnbiasedWithThePlan) {
    // configs/uniform_furnace.toml (radiance 0.5 everywhere) without spp and count: the plan sizes
    // both; one pass per run (the limit is below it), 40 independent runs. The estimates count walks,
    // exact at any k: photon neighbours read high here by the walks' clustering term (k 8: +0.84% +-
    // 0.05% of the image, docs/walk_correlation.md), which is the estimate's, not the plan's.
    const std::string f = write("furnace.toml",
                                "[render]\nwidth = 12\nheight = 12\nintegrator = \"photon_map\"\ntime_limit = 1e-9\n\n"
                                "[camera]\nposition = [0.0, 0.0, 0.0]\nlook_at = [0.0, 0.0, -1.0]\nfov = 90\n\n"
                                "[photons]\nk = 8\ndirect = \"photon_map\"\nmax_radius_mfp = 0\nneighbours = \"walks\"\n\n"
                                "[[lights]]\ntype = \"environment\"\nradiance = 0.5\n\n"
                                "[[media]]\ntype = \"homogeneous\"\nshape = \"sphere\"\nradius = 6.0\nsigma_t_scale = 0.6\nalbedo = 1.0\n");
    const RunConfig config = RunConfig::load(f);
    const test::Sample s = test::repeated_run_brightness(config, 40);
    std::printf("furnace: %.5f +- %.5f (exact 0.5)\n", s.mean(), s.se());
    EXPECT_NEAR(s.mean(), 0.5, 3.0 * s.se());
    EXPECT_LT(s.se(), 0.006) << "too noisy to tell 3.6%";
}

TEST(AutoGather, GatherKeyNamesItsValues) {
    const std::string f = write("cube.toml", thin_cube(1.0));
    try {
        RunConfig::load(f, {"photons.gather=\"bogus\""});
        FAIL() << "accepted photons.gather = \"bogus\"";
    } catch (const ConfigError& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("gather"), std::string::npos) << m;
        EXPECT_NE(m.find("threshold"), std::string::npos) << m;
        EXPECT_NE(m.find("auto"), std::string::npos) << m;
    }
    EXPECT_NO_THROW(RunConfig::load(f, {"photons.gather=\"threshold\""}));
}

// A box at optical depth 1000 (albedo 0.9): every kNN ball spans far more than max_radius_mfp mean
// free paths, so no estimate uses the map (render/plan/no_map_candidate.h). The collision gather's pilot
// samples are then the continuation's, and under render.integrator = "auto" "continue" wins by the
// photon pass it saves: the passes after the pilot's trace no photons, on 1 and 2 threads alike and
// at scale 1e3.
TEST(AutoGather, NoPhotonPassWhereNoQueryUsesTheMap) {
    const std::vector<std::string> sets = {"photons.count=5000", "render.passes=3", "render.spp=3", "render.integrator=\"auto\""};
    auto with = [&](std::vector<std::string> v, const std::string& extra) {
        v.push_back(extra);
        return v;
    };
    std::ostringstream log;
    const std::string f = write("dense.toml", thin_cube(1.0, 1000.0, 0.9));
    const RunResult a = render(f, with(sets, "render.threads=1"), &log);
    const RunResult b = render(f, with(sets, "render.threads=2"));
    const RunResult c = render(write("dense1e3.toml", thin_cube(1e3, 1000.0, 0.9)), with(sets, "render.threads=2"));
    ASSERT_TRUE(PhotonMapStats::of(a.stats).auto_gather && PhotonMapStats::of(b.stats).auto_gather && PhotonMapStats::of(c.stats).auto_gather);
    const AutoGatherStats& x = *PhotonMapStats::of(a.stats).auto_gather;
    ASSERT_EQ(x.candidates.size(), 3u);
    EXPECT_EQ(x.candidates[0].per_sample.map_used, 0.0);   // the collision gather never used the map
    EXPECT_GT(x.candidates[0].per_sample.queries, 0.0);    // though it asked
    EXPECT_EQ(x.chosen, "continue") << log.str();
    EXPECT_FALSE(x.photon_pass);
    EXPECT_EQ(a.stats.integrator_used, "path");
    EXPECT_EQ(a.stats.gather_used, "none");
    EXPECT_NE(log.str().find("integrator: auto chose the path tracer: relative error^2 x work"), std::string::npos) << log.str();
    EXPECT_EQ(PhotonMapStats::of(a.stats).photons->emitted, 5000u);             // pass 0's only, of 3
    ASSERT_TRUE(PhotonMapStats::of(a.stats).photon_ledger);
    EXPECT_EQ(PhotonMapStats::of(a.stats).photon_ledger->pilot_only, 5000u);    // it served the pilot alone
    EXPECT_EQ(PhotonMapStats::of(a.stats).photon_ledger->pass_maps, 0u);
    EXPECT_EQ(a.stats.pass_count(), 3u);
    EXPECT_NE(log.str().find("no photon pass after this one"), std::string::npos) << log.str();
    EXPECT_EQ(log.str().find("exceeds the"), std::string::npos) << log.str();   // no "k exceeds the stored count" warning
    EXPECT_EQ(PhotonMapStats::of(b.stats).auto_gather->chosen, x.chosen);
    EXPECT_EQ(PhotonMapStats::of(c.stats).auto_gather->chosen, x.chosen);
    for (size_t i = 0; i < x.candidates.size(); ++i) {
        EXPECT_EQ(PhotonMapStats::of(b.stats).auto_gather->candidates[i].v_camera, x.candidates[i].v_camera);
        EXPECT_EQ(PhotonMapStats::of(b.stats).auto_gather->candidates[i].sample_cost, x.candidates[i].sample_cost);
    }
    EXPECT_EQ(a.image.rgb, b.image.rgb);
}

// The same box with render.integrator = "photon_map": the plan chooses among the map's gathers only,
// every pass traces its map, and the camera paths continue wherever the estimator's bound says
// (photon/estimate/bounded_radius.h): the honest photon map, with its figures in the sidecar.
TEST(AutoGather, ThePhotonMapKeepsItsMapWhereNoQueryUsesIt) {
    std::ostringstream log;
    const RunResult a = render(write("dense.toml", thin_cube(1.0, 1000.0, 0.9)),
                               {"photons.count=5000", "render.passes=3", "render.spp=3"}, &log);
    ASSERT_TRUE(PhotonMapStats::of(a.stats).auto_gather && PhotonMapStats::of(a.stats).photons);
    const AutoGatherStats& x = *PhotonMapStats::of(a.stats).auto_gather;
    ASSERT_EQ(x.candidates.size(), 2u);
    EXPECT_NE(x.chosen, "continue");
    EXPECT_TRUE(x.photon_pass);
    EXPECT_EQ(PhotonMapStats::of(a.stats).photons->emitted, 3u * 5000u);   // a map per pass
    EXPECT_EQ(a.stats.integrator_used, "photon_map");
    EXPECT_EQ(a.stats.gather_used, x.chosen);
    ASSERT_TRUE(a.stats.map_estimates);
    EXPECT_EQ(log.str().find("integrator: auto chose"), std::string::npos) << log.str();
}

// A medium of density 0 and nothing else: the pilot's map is empty and no surface map is stored,
// so no estimate can use a map and no photon pass follows the pilot's. (Planned with every figure 0
// it traced 1e5 photons per pass, 185 passes in 2 s, for a black image.) With a wall and a floor the
// surface map holds the light between them (direct light is NEE's) and is used: the gathers stay,
// with the photon pass.
TEST(AutoGather, NoPhotonPassWhereTheMediumIsEmptyAndNothingElseIsLit) {
    const std::vector<std::string> sets = {"photons.count=5000", "render.passes=3", "render.spp=3", "render.integrator=\"auto\""};
    std::ostringstream log;
    const RunResult empty = render(write("empty.toml", thin_cube(1.0, 0.0)), sets, &log);
    ASSERT_TRUE(PhotonMapStats::of(empty.stats).auto_gather);
    EXPECT_EQ(PhotonMapStats::of(empty.stats).auto_gather->chosen, "continue") << log.str();
    EXPECT_FALSE(PhotonMapStats::of(empty.stats).auto_gather->photon_pass);
    EXPECT_EQ(PhotonMapStats::of(empty.stats).photons->emitted, 5000u);   // pass 0's only, of 3
    EXPECT_EQ(PhotonMapStats::of(empty.stats).photons->stored, 0u);
    EXPECT_EQ(empty.stats.pass_count(), 3u);
    for (float v : empty.image.rgb) EXPECT_EQ(v, 0.0f);
    // The photon map traces its (empty) map in every pass.
    const RunResult pm = render(write("empty.toml", thin_cube(1.0, 0.0)), {"photons.count=5000", "render.passes=3", "render.spp=3"});
    ASSERT_TRUE(PhotonMapStats::of(pm.stats).auto_gather && PhotonMapStats::of(pm.stats).photons);
    EXPECT_NE(PhotonMapStats::of(pm.stats).auto_gather->chosen, "continue");
    EXPECT_EQ(PhotonMapStats::of(pm.stats).photons->emitted, 3u * 5000u);
    for (float v : pm.image.rgb) EXPECT_EQ(v, 0.0f);

    const RunResult floor = render(write("empty_corner.toml", thin_cube(1.0, 0.0) +
                                                             "[[shapes]]\ntype = \"quad\"\ncenter = [0.5, 0.5, -0.5]\n"
                                                             "u = [3.0, 0.0, 0.0]\nv = [0.0, 3.0, 0.0]\nreflectance = 0.5\n"
                                                             "[[shapes]]\ntype = \"quad\"\ncenter = [0.5, -0.5, 0.5]\n"
                                                             "u = [3.0, 0.0, 0.0]\nv = [0.0, 0.0, -3.0]\nreflectance = 0.5\n"),
                                   sets);
    ASSERT_TRUE(PhotonMapStats::of(floor.stats).auto_gather);
    EXPECT_NE(PhotonMapStats::of(floor.stats).auto_gather->chosen, "continue");
    EXPECT_TRUE(PhotonMapStats::of(floor.stats).auto_gather->photon_pass);
    EXPECT_EQ(PhotonMapStats::of(floor.stats).photons->emitted, 3u * 5000u);
}

// The furnace (radiance 0.5 everywhere) with balls bounded to 0.01 mean free paths: no estimate can
// use the map, the "auto" integrator's plan drops the photon pass, and the continuation keeps the
// image unbiased.
TEST(AutoGather, FurnaceStaysUnbiasedWithoutTheMap) {
    const std::string f = write("furnace_nomap.toml",
                                "[render]\nwidth = 8\nheight = 8\nintegrator = \"auto\"\nspp = 8\n\n"
                                "[camera]\nposition = [0.0, 0.0, 0.0]\nlook_at = [0.0, 0.0, -1.0]\nfov = 90\n\n"
                                "[photons]\nk = 8\ncount = 2000\ndirect = \"photon_map\"\nmax_radius_mfp = 0.01\n\n"
                                "[[lights]]\ntype = \"environment\"\nradiance = 0.5\n\n"
                                "[[media]]\ntype = \"homogeneous\"\nshape = \"sphere\"\nradius = 6.0\nsigma_t_scale = 0.6\nalbedo = 1.0\n");
    const RunConfig config = RunConfig::load(f);
    const RunResult one = render(f, {});
    ASSERT_TRUE(PhotonMapStats::of(one.stats).auto_gather);
    EXPECT_EQ(PhotonMapStats::of(one.stats).auto_gather->chosen, "continue");
    const test::Sample s = test::repeated_run_brightness(config, 16);
    std::printf("furnace: %.5f +- %.5f (exact 0.5)\n", s.mean(), s.se());
    EXPECT_NEAR(s.mean(), 0.5, 3.0 * s.se());
    EXPECT_LT(s.se(), 0.01) << "too noisy to tell 3%";
}

// The plan of one photon-map pass 0 under a 1 s limit at 32x32, and whether later passes are stateless.
static std::pair<std::string, bool> planned_gather_and_stateless(const std::string& file, const char* integrator = "auto") {
    const RunConfig config = RunConfig::load(file, {"render.time_limit=1", "render.width=32", "render.height=32"});
    PhotonMapSettings s = photon_map_settings(config);
    s.chooses_integrator = std::string(integrator) == "auto";
    PhotonMapIntegrator pm(*config.scene, s);
    EXPECT_FALSE(pm.stateless_passes());   // a photon pass per pass until a plan says otherwise
    PassContext context;
    context.progress = false;
    context.configured_spp = 16;
    RunStats stats;
    pm.prepare(context, stats);
    pm.collect(stats, nullptr);
    EXPECT_TRUE(PhotonMapStats::of(stats).auto_gather);
    // The pilot is one-off work: a time limit does not reckon later passes by it (render/run/run.cpp).
    double pilot_seconds = 0.0;
    for (const PhaseStats& phase : stats.phases)
        if (phase.name == "pilot") pilot_seconds += phase.seconds;
    EXPECT_GT(pilot_seconds, 0.0);
    EXPECT_GE(pm.one_off_seconds(), pilot_seconds);
    return {PhotonMapStats::of(stats).auto_gather ? PhotonMapStats::of(stats).auto_gather->chosen : std::string(), pm.stateless_passes()};
}

TEST(AutoGather, APlanWithoutTheMapMakesLaterPassesStateless) {
    // The dense cube (optical thickness 1000, every kNN ball wider than max_radius_mfp) is planned
    // without a map ("continue": counts only, the same on any machine). From then on no pass traces
    // photons, so the run loop may group passes and must not take pass 0's photon pass and pilot for
    // what each later pass costs (render/run/run.cpp).
    const auto dense = planned_gather_and_stateless(write("dense.toml", thin_cube(1.0, 1000.0, 0.9)));
    EXPECT_EQ(dense.first, "continue");
    EXPECT_TRUE(dense.second);
    // The photon-map integrator keeps a photon pass per pass there.
    const auto dense_pm = planned_gather_and_stateless(write("dense.toml", thin_cube(1.0, 1000.0, 0.9)), "photon_map");
    EXPECT_NE(dense_pm.first, "continue");
    EXPECT_FALSE(dense_pm.second);
    // A run that keeps its map keeps a photon pass per pass: the cube at optical thickness 1 and
    // albedo 0.9, where the plan takes the march.
    const auto thin = planned_gather_and_stateless(write("cube1.toml", thin_cube(1.0, 1.0, 0.9)));
    EXPECT_NE(thin.first, "continue");
    EXPECT_FALSE(thin.second);
}

TEST(AutoGather, APlanWithoutTheMapRendersThePathTracersImage) {
    // "continue" is the path tracer's estimator: where the plan drops the map every pass, pass 0
    // included, is the path tracer's, the same samples in the same streams, so the image is the path
    // tracer's to the bit (and no slower per sample than it: the map's bookkeeping at every collision
    // cost 1.2-1.5x, docs/studies/heldout_scenes.md section 23).
    const std::string dense = write("dense_same.toml", thin_cube(1.0, 1000.0, 0.9));
    const std::vector<std::string> sets = {"render.width=16", "render.height=16", "render.spp=8", "render.passes=2"};
    std::vector<std::string> pm = sets, path = sets;
    pm.push_back("render.integrator=\"auto\"");
    path.push_back("render.integrator=\"path\"");
    const RunResult a = render(dense, pm), b = render(dense, path);
    ASSERT_TRUE(PhotonMapStats::of(a.stats).auto_gather);
    EXPECT_EQ(PhotonMapStats::of(a.stats).auto_gather->chosen, "continue");
    ASSERT_GT(b.image.mean(), 0.0);
    EXPECT_EQ(a.image.rgb, b.image.rgb);
}

TEST(AutoGather, ThePathTracerChosenUnderALimitTakesOneSamplePassesUnlessPassesIsSet) {
    // The dense cube, where the "auto" integrator takes the path tracer: under a limit its passes
    // hold one sample per pixel, as render.integrator = "path" does, however render.spp is set;
    // render.passes pins spp / passes.
    const std::string dense = write("dense_limit.toml", thin_cube(1.0, 1000.0, 0.9));
    const std::vector<std::string> sets = {"render.width=16", "render.height=16", "render.spp=8",
                                           "render.integrator=\"auto\"", "render.time_limit=1e-3"};
    const RunResult sized = render(dense, sets);
    ASSERT_EQ(sized.stats.integrator_used, "path");
    EXPECT_EQ(sized.stats.render.samples, 256u * sized.stats.pass_count());
    for (const auto& w : sized.stats.warnings) EXPECT_EQ(w.find("render.spp is set"), std::string::npos) << w;
    std::vector<std::string> pinned = sets;
    pinned.push_back("render.passes=2");
    const RunResult given = render(dense, pinned);
    ASSERT_EQ(given.stats.integrator_used, "path");
    EXPECT_EQ(given.stats.render.samples, 256u * 4u * given.stats.pass_count());
}

TEST(AutoGather, ThePlanSizesPassesForTheTimeLeftAfterItsPilot) {
    // The thin cube at 64 x 64 under a 0.3-s limit: the pilot's counted one-off work
    // (its samples, the half maps' build; the pilot map where pass 0 does not reuse it) is taken off
    // the budget before the passes are sized, from counts alone: the same on 1 and 2 threads.
    const std::string f = write("cube_left.toml", thin_cube(1.0, 0.3, 0.9));
    std::vector<AutoGatherStats> plans;
    for (const char* threads : {"render.threads=1", "render.threads=2"}) {
        std::ostringstream log;
        const RunResult r = render(f, {"render.width=64", "render.height=64", "render.time_limit=0.3", threads}, &log);
        ASSERT_TRUE(PhotonMapStats::of(r.stats).auto_gather);
        const AutoGatherStats& a = *PhotonMapStats::of(r.stats).auto_gather;
        ASSERT_TRUE(a.photon_pass) << log.str();
        EXPECT_EQ(a.budget, 0.3 * kWorkUnitsPerSecond);
        EXPECT_GT(a.pilot_work, 0.0) << log.str();
        EXPECT_LT(a.pilot_work, a.budget) << log.str();
        // The chosen pass fits twice in what the pilot left (the smallest pass aside, which is kept).
        const GatherMeasurement* chosen = nullptr;
        for (const GatherMeasurement& m : a.candidates)
            if (m.name == a.chosen) chosen = &m;
        ASSERT_NE(chosen, nullptr);
        const double pass = a.photon_cost * double(a.count) + 64.0 * 64.0 * a.spp * chosen->sample_cost;
        if (a.spp > 1) {
            EXPECT_LE(pass, (a.budget - a.pilot_work) / kPlanMinPasses) << log.str();
        }
        EXPECT_NE(log.str().find("less the pilot's counted"), std::string::npos) << log.str();
        plans.push_back(a);
    }
    EXPECT_EQ(plans[0].pilot_work, plans[1].pilot_work);
    EXPECT_EQ(plans[0].count, plans[1].count);
    EXPECT_EQ(plans[0].spp, plans[1].spp);
    EXPECT_EQ(plans[0].chosen, plans[1].chosen);
}
