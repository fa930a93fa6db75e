// render/photon_map/beam_pass_size.h: photons and samples per photon-beams pass from two pilots'
// counted work, so that a pass fits render.time_limit / kBeamPlanMinPasses.
#include <gtest/gtest.h>

#include <cmath>

#include "render/photon_map/beam_pass_size.h"

using namespace vpm;

namespace {

// A pilot of n photons: 0.5 beams per photon, 4 pieces per beam, one segment query per sample with
// tests_per_query crossing tests, width_tests per beam.
BeamPilotCounts pilot(double n, double tests_per_query, double width_tests) {
    BeamPilotCounts c;
    c.photons = n;
    c.beams = 0.5 * n;
    c.pieces = 4.0 * c.beams;
    c.width_tests = width_tests * c.beams;
    c.collisions = 0.4 * n;
    c.samples = 512.0;
    c.beam_queries = 512.0;
    c.beam_tests = 512.0 * tests_per_query;
    return c;
}

BeamPassInputs inputs(double seconds, bool size_photons, bool size_samples) {
    BeamPassInputs in;
    in.small = pilot(1024.0, 100.0, 0.0);
    in.large = pilot(4096.0, 100.0, 0.0);
    in.units = WorkUnits{};
    in.units.path = 100.0;
    in.units.collision = 400.0;
    in.beam_units = beam_work_units();
    in.pixels = 65536.0;   // 256 x 256
    in.count = 400000;
    in.spp = 16;
    in.size_photons = size_photons;
    in.size_samples = size_samples;
    in.budget = seconds * kWorkUnitsPerSecond;
    return in;
}

}  // namespace

TEST(BeamPassSize, TheChosenPassFitsItsShareOfTheBudget) {
    const BeamPassInputs in = inputs(8.0, true, true);
    const BeamPassSize b = size_beam_pass(in);
    EXPECT_TRUE(b.fits);
    EXPECT_LE(b.pass_units, (in.budget - b.pilot_units) / kBeamPlanMinPasses);
    EXPECT_LT(b.count, in.count);   // 400,000 photons at 1 spp do not fit 2 s of one core here
    EXPECT_EQ(b.spp, 1);
    // The next larger N would not fit: the largest that does is taken.
    EXPECT_GT(beam_pass_units(in, double(b.count) * 2.0, double(b.spp)), b.pass_budget);
}

TEST(BeamPassSize, AmpleBudgetKeepsTheConfiguredSizes) {
    const BeamPassSize b = size_beam_pass(inputs(1e6, true, true));
    EXPECT_EQ(b.count, 400000);
    EXPECT_EQ(b.spp, 16);
    EXPECT_TRUE(b.fits);
}

TEST(BeamPassSize, PinnedSizesStayAndSayTheyDoNotFit) {
    const BeamPassSize b = size_beam_pass(inputs(8.0, false, false));
    EXPECT_EQ(b.count, 400000);
    EXPECT_EQ(b.spp, 16);
    EXPECT_FALSE(b.fits);
}

TEST(BeamPassSize, PinnedPhotonsSizeTheSamples) {
    BeamPassInputs in = inputs(8.0, false, true);
    in.count = 4096;
    in.pixels = 4096.0;
    const BeamPassSize b = size_beam_pass(in);
    EXPECT_EQ(b.count, 4096);
    EXPECT_GT(b.spp, 1);
    EXPECT_TRUE(b.fits);
    if (b.spp < in.spp) {
        EXPECT_GT(beam_pass_units(in, 4096.0, double(2 * b.spp)), b.pass_budget);
    }
}

TEST(BeamPassSize, GrowthIsFittedAndAtLeastTheFloor) {
    BeamPassInputs in = inputs(8.0, true, true);
    // Tests per query 100 at 1,024 photons and 400 at 4,096: N^1.
    in.small = pilot(1024.0, 100.0, 10.0);
    in.large = pilot(4096.0, 400.0, 10.0);
    const BeamPassSize b = size_beam_pass(in);
    EXPECT_NEAR(b.test_growth, 1.0, 1e-12);
    EXPECT_NEAR(b.width_growth, 0.75, 1e-12);   // flat in the pilots: the floor
    // A pass of 16 x the large pilot's photons then costs 16 x its tests per query per sample.
    const double at_large = beam_pass_units(in, 4096.0, 1.0), at_16 = beam_pass_units(in, 16.0 * 4096.0, 1.0);
    EXPECT_GT(at_16, 8.0 * at_large);
}

TEST(BeamPassSize, PointBeamGrowthFloorIsTheDiscs) {
    // point_beam: flat pilots read growth 0; the discs crossed per segment grow at least as N^(1/3).
    // 32 s: a 256 x 256 image's segment queries at 20,000 units each fit a quarter of it.
    BeamPassInputs in = inputs(32.0, true, true);
    in.beam_units = point_beam_work_units(5000.0);
    in.least_test_growth = kLeastDiscTestGrowth;
    const BeamPassSize b = size_beam_pass(in);
    EXPECT_NEAR(b.test_growth, 1.0 / 3.0, 1e-12);
    EXPECT_TRUE(b.fits);
    // Cheaper growth than photon beams' floor: at least as many photons fit the same budget.
    BeamPassInputs beams = inputs(32.0, true, true);
    beams.beam_units = in.beam_units;
    EXPECT_GE(b.count, size_beam_pass(beams).count);
}

TEST(BeamPassSize, LeastSamplesComeBeforePhotonsAndGiveWayWhereNothingFits) {
    // photon_beams: S starts at least_spp, the photons are halved until that pass fits.
    BeamPassInputs in = inputs(8.0, true, true);
    in.pixels = 4096.0;   // 64 x 64
    in.least_spp = 4;
    const BeamPassSize b = size_beam_pass(in);
    EXPECT_TRUE(b.fits);
    EXPECT_GE(b.spp, 4);
    BeamPassInputs one = in;
    one.least_spp = 1;
    const BeamPassSize from_one = size_beam_pass(one);
    EXPECT_LE(b.count, from_one.count);   // fewer photons (or as many) for the samples
    // A budget too small for least_spp at the fewest photons: S falls back as far as 1.
    in.pixels = 65536.0 * 64.0;
    const BeamPassSize tight = size_beam_pass(in);
    EXPECT_EQ(tight.count, 1024);
    EXPECT_EQ(tight.spp, 1);
}

TEST(BeamPassSize, BalanceMovesWorkFromPhotonsToSamples) {
    // Photons priced high: at the largest N that fits at 1 spp the photon side holds most of the
    // pass; balanced, N halves and S doubles while the photons hold more than half and it fits.
    BeamPassInputs in = inputs(8.0, true, true);
    in.units.path = 20000.0;
    in.pixels = 4096.0;
    const BeamPassSize largest = size_beam_pass(in);
    in.balance_camera = true;
    const BeamPassSize b = size_beam_pass(in);
    EXPECT_TRUE(b.fits);
    EXPECT_LT(b.count, largest.count);
    EXPECT_GT(b.spp, largest.spp);
    // One more step would leave the photons at most half, or not fit.
    double map = 0.0;
    const double pass = beam_pass_units(in, double(b.count), double(b.spp), &map);
    const bool photons_half_or_less = !(2.0 * map > pass);
    const bool next_does_not_fit = beam_pass_units(in, double(b.count / 2), double(b.spp * 2)) > b.pass_budget;
    EXPECT_TRUE(photons_half_or_less || next_does_not_fit || b.spp * 2 > in.spp || b.count / 2 < 1024);
}
