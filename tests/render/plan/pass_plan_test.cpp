// render/plan/pass_plan.h: photons and samples per pass and the gather from measured variances and
// counted costs, minimising (V_map(N) + V_camera / S) x C(N, S).
#include <gtest/gtest.h>

#include <cmath>

#include "core/error.h"
#include "core/math.h"
#include "render/plan/no_map_candidate.h"
#include "render/plan/pass_plan.h"

using namespace vpm;

namespace {

// A candidate's pilot figures, the rest of GatherMeasurement at its defaults.
GatherMeasurement measured(const char* name, double v_camera, double v_half, double v_quarter, double sample_cost,
                           double max_weight = 0.0) {
    GatherMeasurement m;
    m.name = name;
    m.v_camera = v_camera;
    m.v_map_half = v_half;
    m.v_map_quarter = v_quarter;
    m.sample_cost = sample_cost;
    m.max_weight = max_weight;
    return m;
}

PlanInputs inputs(double v_camera, double v_half, double v_quarter, double sample_cost, double photon_cost) {
    PlanInputs in;
    in.candidates = {measured("collision", v_camera, v_half, v_quarter, sample_cost)};
    in.photon_cost = photon_cost;
    in.pixels = 1000.0;
    in.count = 1000;
    in.spp = 16;
    in.size_photons = in.size_samples = true;
    return in;
}

double score(const PlanInputs& in, double n, double s, double beta) {
    const GatherMeasurement& m = in.candidates[0];
    const double v_map = m.v_map_half * std::pow(0.5 * double(in.count) / n, beta);
    return (v_map + m.v_camera / s) * (in.photon_cost * n + in.pixels * s * m.sample_cost);
}

// A map gather (V_camera 1, V_map at N0/2 v_half) and the continuation (V_camera v_none) at the same
// cost per sample and no photon cost, at the configured sizes: only the choice is the plan's.
PlanInputs map_and_continuation(double v_half, double v_none) {
    PlanInputs in = inputs(/*v_camera*/ 1.0, v_half, /*v_quarter*/ -1.0, /*sample*/ 100.0, /*photon*/ 0.0);
    in.size_photons = in.size_samples = false;
    GatherMeasurement none = in.candidates[0];
    none.name = kNoMapCandidate;
    none.uses_map = false;
    none.v_camera = v_none;
    none.v_map_half = 0.0;
    in.candidates.push_back(none);
    return in;
}

}  // namespace

TEST(PassPlan, ExponentFromHalfAndQuarterMaps) {
    bool measured = false;
    EXPECT_NEAR(map_variance_exponent(1.0, 2.0, measured), 1.0, 1e-12);
    EXPECT_TRUE(measured);
    EXPECT_NEAR(map_variance_exponent(1.0, std::pow(2.0, 0.5), measured), 0.5, 1e-12);
    EXPECT_NEAR(map_variance_exponent(1.0, 8.0, measured), 1.0, 1e-12);          // faster than 1/N: pilot noise
    EXPECT_NEAR(map_variance_exponent(1.0, 1.0, measured), 1.0 / 3.0, 1e-12);    // flat: at most one ball per pixel
    EXPECT_EQ(map_variance_exponent(-1.0, 2.0, measured), 1.0);
    EXPECT_FALSE(measured);
    EXPECT_EQ(map_variance_exponent(1.0, -1.0, measured), 1.0);
    EXPECT_FALSE(measured);
}

TEST(PassPlan, PicksTheLeastErrorTimesCostOnItsGrid) {
    // beta = 1: V_map(N) = a / N, and the optimum of (a/N + b/S)(cN N + cS S) over the grid.
    const PlanInputs in = inputs(/*v_camera*/ 4.0, /*v_half*/ 0.02, /*v_quarter*/ 0.04, /*sample*/ 50.0, /*photon*/ 200.0);
    const PassPlan p = plan_passes(in);
    EXPECT_TRUE(p.beta_measured);
    EXPECT_NEAR(p.beta, 1.0, 1e-12);
    const double best = score(in, double(p.count), double(p.spp), 1.0);
    ASSERT_EQ(p.score.size(), 1u);
    EXPECT_NEAR(p.score[0], best, 1e-9 * best);
    for (int i = 0; i <= kPlanMaxPhotonDoublings; ++i)
        for (int s = 1; s <= kPlanMaxSpp; s *= 2) EXPECT_LE(best, score(in, 1000.0 * (1 << i), s, 1.0)) << i << " " << s;
    // Camera noise dominating and cheap samples: more samples per pass than configured.
    EXPECT_GT(p.spp, 16);
}

TEST(PassPlan, MapNoiseBuysPhotonsAndCameraNoiseBuysSamples) {
    const PassPlan map_bound = plan_passes(inputs(0.01, 1.0, 2.0, 10.0, 10.0));
    const PassPlan camera_bound = plan_passes(inputs(100.0, 1e-6, 2e-6, 10.0, 10.0));
    EXPECT_GT(map_bound.count, camera_bound.count);
    EXPECT_LT(map_bound.spp, camera_bound.spp);
    EXPECT_EQ(camera_bound.count, 1000);   // never below the configured count (the bias stays at most its)
}

TEST(PassPlan, KeepsGivenSizesAndPicksTheGather) {
    PlanInputs in = inputs(1.0, 0.1, 0.2, 10.0, 100.0);
    in.candidates.push_back(measured("march", 0.1, 0.01, 0.02, 40.0, 1.0));   // 10x less variance at 4x the samples' cost
    in.size_photons = in.size_samples = false;
    const PassPlan p = plan_passes(in);
    EXPECT_EQ(p.count, 1000);
    EXPECT_EQ(p.spp, 16);
    EXPECT_EQ(p.chosen, 1);
    ASSERT_EQ(p.score.size(), 2u);
    EXPECT_LT(p.score[1], p.score[0]);
    // Scale-invariant: all variances times 7 and all costs times 3 change nothing.
    for (auto& c : in.candidates) {
        c.v_camera *= 7;
        c.v_map_half *= 7;
        c.v_map_quarter *= 7;
        c.sample_cost *= 3;
    }
    in.photon_cost *= 3;
    EXPECT_EQ(plan_passes(in).chosen, 1);
}

TEST(PassPlan, NothingLitGoesToTheCheaperGather) {
    PlanInputs in = inputs(0.0, 0.0, 0.0, 30.0, 10.0);
    in.candidates.push_back(measured("march", 0.0, 0.0, 0.0, 20.0, 1.0));
    const PassPlan p = plan_passes(in);
    EXPECT_EQ(p.chosen, 1);
    EXPECT_EQ(p.spp, 1);
    EXPECT_EQ(p.count, 1000);
}

TEST(PassPlan, RefusesEmptyOrNonPositiveInputs) {
    PlanInputs in = inputs(1.0, 0.1, 0.2, 10.0, 100.0);
    in.candidates.clear();
    EXPECT_THROW(plan_passes(in), Error);
    in = inputs(1.0, 0.1, 0.2, 10.0, 100.0);
    in.pixels = 0.0;
    EXPECT_THROW(plan_passes(in), Error);
}

TEST(PassPlan, ABudgetBuysPhotonsAgainstTheBias) {
    // The bias does not average over passes: with a budget it costs bias(N)^2 T whatever the pass
    // sizes, and N^-4/3 of it is bought back with photons; without a budget it is left out.
    PlanInputs in = inputs(/*v_camera*/ 1e-3, /*v_half*/ 1e-6, /*v_quarter*/ 2e-6, /*sample*/ 10.0, /*photon*/ 100.0);
    in.candidates[0].bias2 = 1e-2;
    const PassPlan none = plan_passes(in);
    EXPECT_EQ(none.count, 1000);
    in.budget = 1e9;
    const PassPlan big = plan_passes(in);
    EXPECT_EQ(big.count, 1000 << kPlanMaxPhotonDoublings);
    // The score is error^2 x time at the chosen sizes: (variance / whole passes + bias^2) x budget.
    const double n = double(big.count), cost = 100.0 * n + 1000.0 * big.spp * 10.0;
    const double expect = ((1e-6 * std::pow(500.0 / n, 1.0) + 1e-3 / big.spp) / std::floor(1e9 / cost) +
                           1e-2 * std::pow(1000.0 / n, 4.0 / 3.0)) * 1e9;
    EXPECT_NEAR(big.score[0], expect, 1e-9 * expect);
    // No pass fits: passes no larger than the configured one (1000 photons, 16 samples), scored as
    // one pass each, (variance + bias^2) x cost.
    in.budget = 1.0;
    const PassPlan tiny = plan_passes(in);
    EXPECT_EQ(tiny.count, 1000);
    EXPECT_LE(tiny.spp, 16);
    const double c = 100.0 * 1000.0 + 1000.0 * tiny.spp * 10.0;
    EXPECT_NEAR(tiny.score[0], (1e-6 * 0.5 + 1e-3 / tiny.spp + 1e-2) * c, 1e-9 * c);
}

TEST(PassPlan, PassesStayWithinTheBudgetsShareAndHeavyTailedMarchesAreNotTrusted) {
    PlanInputs in = inputs(/*v_camera*/ 1e-3, /*v_half*/ 1.0, /*v_quarter*/ 2.0, /*sample*/ 10.0, /*photon*/ 100.0);
    in.budget = kPlanMinPasses * (100.0 * 4000.0 + 1000.0 * 4 * 10.0);   // the cap: 4000 photons and 4 samples
    const PassPlan p = plan_passes(in);
    EXPECT_LE(100.0 * double(p.count) + 1000.0 * p.spp * 10.0, in.budget / kPlanMinPasses);
    // The map's noise dominates: the plan buys as many photons over the budget as fit (4000 x 2
    // passes; with the cost mostly photons, 1000 x 8 passes is the same variance).
    EXPECT_EQ(double(p.count) * std::floor(in.budget / (100.0 * double(p.count) + 1000.0 * p.spp * 10.0)), 8000.0);
    // The march measures 100x less variance but its points weighed up to 50: not trusted.
    in.candidates.push_back(measured("march", 1e-5, 1e-2, 2e-2, 10.0, 50.0));
    EXPECT_EQ(plan_passes(in).chosen, 0);
    in.candidates[1].max_weight = 1.0;
    EXPECT_EQ(plan_passes(in).chosen, 1);
    // A march whose pilot mean is far from the collision gather's missed a tail: not trusted.
    in.candidates[0].mean = 1.0;
    in.candidates[0].mean_se = 0.01;
    in.candidates[1].mean = 0.2;
    in.candidates[1].mean_se = 0.001;
    EXPECT_EQ(plan_passes(in).chosen, 0);
    in.candidates[1].mean = 0.97;   // within 4 SE: trusted
    EXPECT_EQ(plan_passes(in).chosen, 1);
}

TEST(PassPlan, ACandidateWhoseMeanAgreesWithNoOtherIsNotTrusted) {
    // The thin blob's pilot (pass_plan.cpp): the collision gather scores best on a mean its few
    // collisions left 3.5x low, while the march and the continuation agree. Both of those are trusted
    // and the collision gather is not, though it is the first candidate.
    PlanInputs in = inputs(/*v_camera*/ 4e-5, /*v_half*/ 0.0, /*v_quarter*/ -1.0, /*sample*/ 420.0, /*photon*/ 300.0);
    in.candidates[0].mean = 0.00041;
    in.candidates[0].mean_se = 0.00029;
    GatherMeasurement march = in.candidates[0];
    march.name = "march";
    march.v_camera = 1.5e-7;
    march.sample_cost = 14500.0;
    march.mean = 0.00142;
    march.mean_se = 0.00032;
    GatherMeasurement none = march;
    none.name = kNoMapCandidate;
    none.uses_map = false;
    none.v_camera = 8e-5;
    none.sample_cost = 350.0;
    none.mean = 0.00146;
    in.candidates.push_back(march);
    in.candidates.push_back(none);
    PassPlan p = plan_passes(in);
    EXPECT_EQ(p.chosen, 1);
    EXPECT_EQ(p.score[0], kInfinity);
    EXPECT_LT(p.score[1], p.score[2]);
    // Its mean within 2 SE of theirs (and resolved): all three are trusted, and the march still wins
    // on its score (variance x cost 0.0022 against 0.017).
    in.candidates[0].mean = 0.0012;
    in.candidates[0].mean_se = 0.0002;
    p = plan_passes(in);
    EXPECT_LT(p.score[0], kInfinity);
    EXPECT_GT(p.score[0], p.score[1]);
    EXPECT_EQ(p.chosen, 1);
    // No two resolved means agree (the march far off, the continuation unresolved): the collision
    // gather is the reference again, and the march, far from it, is not trusted.
    in.candidates[1].mean = 0.0001;
    in.candidates[1].mean_se = 0.00001;
    in.candidates[2].mean_se = 0.001;
    p = plan_passes(in);
    EXPECT_EQ(p.score[1], kInfinity);
    EXPECT_LT(p.score[2], kInfinity);
}

TEST(PassPlan, APassThatFillsTheBudgetTakesAllTheSamplesItHolds) {
    // Photons dear (1e6 units a pass of 1000) against a budget of one configured pass (1000 photons,
    // 16 samples): every pass is the only one, so the map's noise does not average over passes and
    // more samples cost nothing that matters. Taking T / C as the pass count, the plan chose 1 sample
    // (cornell_smoke at a 4 s limit: one pass of 1 sample, the image 12% low on one seed).
    PlanInputs in = inputs(/*v_camera*/ 1e-2, /*v_half*/ 2.0, /*v_quarter*/ 4.0, /*sample*/ 10.0, /*photon*/ 1000.0);
    in.size_photons = false;
    in.budget = 1000.0 * 1000.0 + 1000.0 * 16.0 * 10.0;
    const PassPlan p = plan_passes(in);
    EXPECT_EQ(p.count, 1000);
    EXPECT_EQ(p.spp, 16);
}

TEST(PassPlan, ContinueCompetesWithLongPathsWhereTheMapIsUsed) {
    // render/plan/no_map_candidate.h: "continue" (no map) with long paths (19 tracked segments per sample,
    // the dense albedo-0.99 box) beside a gather that used the map in every query is scored like any
    // candidate: it wins where its error^2 x work is lower, and loses where it is not.
    PlanInputs in = inputs(/*v_camera*/ 1e-2, /*v_half*/ 1e-4, /*v_quarter*/ 2e-4, /*sample*/ 10.0, /*photon*/ 100.0);
    in.candidates[0].per_sample.queries = 1.0;
    in.candidates[0].per_sample.map_used = 1.0;
    GatherMeasurement none = in.candidates[0];
    none.name = kNoMapCandidate;
    none.uses_map = false;
    none.v_camera = 1e-3;
    none.v_map_half = 0.0;
    none.per_sample.rays = 19.0;
    none.per_sample.queries = none.per_sample.map_used = 0.0;
    in.candidates.push_back(none);
    std::vector<GatherMeasurement> c = in.candidates;
    exclude_maps_that_go_unused(c);
    EXPECT_FALSE(c[0].excluded);
    EXPECT_FALSE(c[1].excluded);
    in.candidates = c;
    EXPECT_EQ(plan_passes(in).chosen, 1);
    // Ten times noisier per sample than the gather it is no longer the better choice.
    in.candidates[1].v_camera = 1e-1;
    EXPECT_EQ(plan_passes(in).chosen, 0);
}

TEST(PassPlan, AMapThatGoesUnusedIsNoChoiceBesideTheContinuation) {
    // render/plan/no_map_candidate.h: the box at 1000 optical depths and albedo 0.99, where every kNN ball
    // is wider than max_radius_mfp. The march scores best on pilot samples that missed the continued
    // paths' tail, but it is the continuation plus a photon pass: not a choice where "continue" is.
    PlanInputs in = inputs(/*v_camera*/ 1e-3, /*v_half*/ 0.0, /*v_quarter*/ -1.0, /*sample*/ 2000.0, /*photon*/ 9000.0);
    in.candidates[0].per_sample.queries = 1.0;
    GatherMeasurement march = in.candidates[0];
    march.name = "march";
    march.v_camera = 1e-5;
    march.per_sample.queries = 11.7;
    march.per_sample.map_used = 0.0;
    GatherMeasurement none = in.candidates[0];
    none.name = kNoMapCandidate;
    none.uses_map = false;
    none.v_camera = 1e-2;   // one tail sample in its pilot
    none.sample_cost = 700.0;
    in.candidates.push_back(march);
    in.candidates.push_back(none);
    std::vector<GatherMeasurement> c = in.candidates;
    exclude_maps_that_go_unused(c);
    EXPECT_TRUE(c[0].excluded);    // no query used either
    EXPECT_TRUE(c[1].excluded);
    EXPECT_FALSE(c[2].excluded);
    in.candidates = c;
    EXPECT_EQ(plan_passes(in).chosen, 2);
    // A map used in more than kNoMapMaxUsedShare of its queries stays a choice.
    c[1] = march;
    c[1].per_sample.map_used = 0.5;
    c[1].excluded = false;
    c[0].excluded = false;
    exclude_maps_that_go_unused(c);
    EXPECT_FALSE(c[1].excluded);
    EXPECT_TRUE(c[0].excluded);
    // Without the continuation as a choice the map candidates stay (nothing else would be left).
    c = {in.candidates[0], march, none};
    c[0].excluded = false;
    c[2].excluded = true;
    exclude_maps_that_go_unused(c);
    EXPECT_FALSE(c[0].excluded);
    EXPECT_FALSE(c[1].excluded);
}

TEST(PassPlan, WithoutTheMapThePassIsTheSmallestTheRunLoopGroups) {
    // Without a map every sample count scores alike; the plan takes the smallest pass of at least
    // kNoMapPassSamples camera samples (the run loop groups such passes, so a time limit cuts them
    // finely), with and without a budget.
    PlanInputs in = inputs(/*v_camera*/ 1e-2, /*v_half*/ 1e-4, /*v_quarter*/ 2e-4, /*sample*/ 475.0, /*photon*/ 1000.0);
    in.pixels = 64.0 * 64.0;
    GatherMeasurement none = in.candidates[0];
    none.name = kNoMapCandidate;
    none.uses_map = false;
    none.v_camera = 1e-6;   // far ahead of the map candidates
    none.v_map_half = 0.0;
    in.candidates.push_back(none);
    for (const double budget : {0.0, 8e9, 123456789.0}) {
        in.budget = budget;
        const PassPlan p = plan_passes(in);
        ASSERT_EQ(p.chosen, int(in.candidates.size()) - 1) << budget;
        EXPECT_EQ(p.spp, 16) << budget;   // 16 x 4096 = kNoMapPassSamples
    }
}

TEST(PassPlan, LargerMapsPriceTheirQueriesHigher) {
    // query_doubling: each used query of a sample costs that much more per doubling of the photons.
    // The plan's score at every (N, S) is the one with the grown price, and a price that grows
    // steeply makes the plan buy fewer photons than a flat one would.
    PlanInputs flat = inputs(/*v_camera*/ 1.0, /*v_half*/ 0.5, /*v_quarter*/ 1.0, /*sample*/ 100.0, /*photon*/ 1.0);
    flat.candidates[0].per_sample.queries = 2.0;
    flat.candidates[0].per_sample.map_used = 1.5;   // 1.5 used queries per sample
    PlanInputs grows = flat;
    grows.query_doubling = 40.0;
    const PassPlan a = plan_passes(flat), b = plan_passes(grows);
    const GatherMeasurement& m = grows.candidates[0];
    const int i = int(std::lround(std::log2(double(b.count) / 1000.0)));
    const double v = m.v_map_half * (0.5 * 1000.0 / double(b.count)) + m.v_camera / b.spp;
    const double cost = double(b.count) + 1000.0 * b.spp * (100.0 + i * 40.0 * 1.5);
    EXPECT_NEAR(b.score[0], v * cost, 1e-9 * v * cost);
    EXPECT_GT(a.count, 1000);   // the flat price buys photons here
    EXPECT_LT(b.count, a.count);
}

TEST(PassPlan, EveryCandidatesVarianceIsChargedAtItsUpperBound) {
    // A map gather and the continuation at the same cost: the continuation's variance read 0.8 of the
    // map's. Read exactly it wins; read from a few samples (relative SE 0.2: charged 1.4x) it loses to
    // an exact map, and wins again where the map's figure is as uncertain (0.25: 1.5x).
    PlanInputs in = map_and_continuation(/*v_half*/ 0.0, /*v_none*/ 0.8);
    EXPECT_EQ(plan_passes(in).chosen, 1);
    in.candidates[1].v_camera_rel_se = 0.2;
    EXPECT_EQ(plan_passes(in).chosen, 0);
    in.candidates[0].v_camera_rel_se = 0.25;
    const PassPlan p = plan_passes(in);
    EXPECT_EQ(p.chosen, 1);
    EXPECT_NEAR(p.score[1] / p.score[0], 0.8 * (1.0 + kPlanVarianceSigmas * 0.2) / (1.0 + kPlanVarianceSigmas * 0.25), 1e-12);
}

TEST(PassPlan, TheBoundChoosesAndTheFigureReadSizes) {
    // A camera variance read from few samples (relative SE 1.5: bound 4x the figure) raises the
    // candidate's score, not its samples per pass: those come from the figure read, as without it.
    PlanInputs in = inputs(/*v_camera*/ 4.0, /*v_half*/ 0.02, /*v_quarter*/ 0.04, /*sample*/ 50.0, /*photon*/ 200.0);
    const PassPlan read = plan_passes(in);
    in.candidates[0].v_camera_rel_se = 1.5;
    const PassPlan bound = plan_passes(in);
    EXPECT_EQ(bound.spp, read.spp);
    EXPECT_EQ(bound.count, read.count);
    EXPECT_GT(bound.score[0], read.score[0]);
    // The map's variance read with a standard error (its bound 6x the figure at N0/2) likewise.
    in.candidates[0].v_map_half_se = 0.05;
    const PassPlan both = plan_passes(in);
    EXPECT_EQ(both.spp, read.spp);
    EXPECT_EQ(both.count, read.count);
    EXPECT_GT(both.score[0], bound.score[0]);
    in.candidates[0].v_map_half_se = 0.0;
    // At the bound's own optimum the samples per pass would double (S* ~ sqrt(V_camera)).
    in.candidates[0].v_camera *= 1.0 + kPlanVarianceSigmas * 1.5;
    in.candidates[0].v_camera_rel_se = 0.0;
    EXPECT_GT(plan_passes(in).spp, read.spp);
}

TEST(PassPlan, TheMapsVarianceIsChargedAtItsUpperBoundToo) {
    // A map gather whose map variance, read as is, leaves it ahead of the continuation (0.005 + 1/16
    // per pass against 1.2/16 at the same cost): read with a standard error of 0.01 at N0/2 (charged
    // 0.03, 0.015 at N0) it falls behind (its passes come from the figure read: TheBoundChoosesAndTheFigureReadSizes).
    PlanInputs in = map_and_continuation(/*v_half*/ 0.01, /*v_none*/ 1.2);
    EXPECT_EQ(plan_passes(in).chosen, 0);
    in.candidates[0].v_map_half_se = 0.01;
    const PassPlan p = plan_passes(in);
    EXPECT_EQ(p.chosen, 1);
    EXPECT_NEAR(p.score[0] / p.score[1], (0.015 + 1.0 / 16.0) / (1.2 / 16.0), 1e-12);

}

TEST(PassPlan, APilotMapSmallerThanN0IsReadAtItsOwnCount) {
    // The figures of a pilot map of N0 / 4 photons (render/photon_map/photon_pass.h) are those of an N0 map
    // scaled to N0 / 4: 4x the map variance, 4^(4/3) the squared bias, queries two doublings
    // cheaper. Read at its own count it plans exactly as the N0 map does, and never below N0.
    PlanInputs full = inputs(/*v_camera*/ 1e-3, /*v_half*/ 1e-4, /*v_quarter*/ -1.0, /*sample*/ 10.0, /*photon*/ 100.0);
    full.candidates[0].bias2 = 1e-5;
    full.candidates[0].per_sample.queries = full.candidates[0].per_sample.map_used = 1.0;
    full.query_doubling = 0.5;
    full.budget = 1e9;
    PlanInputs small = full;
    small.pilot_count = full.count / 4;
    small.candidates[0].v_map_half *= 4.0;
    small.candidates[0].bias2 *= std::pow(4.0, 4.0 / 3.0);
    small.candidates[0].sample_cost -= 2.0 * full.query_doubling;
    const PassPlan a = plan_passes(full), b = plan_passes(small);
    EXPECT_EQ(a.count, b.count);
    EXPECT_EQ(a.spp, b.spp);
    EXPECT_GE(b.count, full.count);
    ASSERT_EQ(a.score.size(), 1u);
    EXPECT_NEAR(b.score[0], a.score[0], 1e-9 * a.score[0]);
    // Read as if at N0, the same figures score worse (the small map's noise taken for N0's).
    PlanInputs misread = small;
    misread.pilot_count = 0;
    EXPECT_GT(plan_passes(misread).score[0], 1.5 * a.score[0]);
}

TEST(PassPlan, APhotonPassOverTheBudgetsShareHalvesThePhotonsUntilThePassFits) {
    // N0 = 100000 photons at 10 units each (1e6) against a cap of 3e5 (budget / kPlanMinPasses): the
    // photons are sized, so N halves to 25000 (2.5e5 + one sample per pixel, 1e4), where the pass fits.
    PlanInputs in = inputs(/*v_camera*/ 1e-3, /*v_half*/ 1e-4, /*v_quarter*/ -1.0, /*sample*/ 10.0, /*photon*/ 10.0);
    in.count = 100000;
    in.budget = kPlanMinPasses * 3e5;
    const PassPlan p = plan_passes(in);
    EXPECT_EQ(p.count, 25000);
    EXPECT_LE(10.0 * double(p.count) + 1000.0 * p.spp * 10.0, 3e5);
    // Pinned photons stay, over the whole budget: no smaller pass can be made.
    in.size_photons = false;
    EXPECT_EQ(plan_passes(in).count, 100000);
    // Where the camera pass of one sample is the larger part (1e6 against the photons' 1e6 / 2^h),
    // fewer photons would not make the pass fit: N stays N0.
    in.size_photons = true;
    in.candidates[0].sample_cost = 1000.0;
    EXPECT_EQ(plan_passes(in).count, 100000);
    // A cap of 30000 takes N down to 1562 (15620 + 1e4), one halving short of kPlanMinPhotons.
    in.candidates[0].sample_cost = 10.0;
    in.budget = kPlanMinPasses * 30000.0;
    EXPECT_EQ(plan_passes(in).count, 1562);
    // A cap of 20000 is below even that: N stops at 1562 (the next halving would pass
    // kPlanMinPhotons), and the run is one pass of any size within the budget.
    in.budget = kPlanMinPasses * 20000.0;
    EXPECT_GE(plan_passes(in).count, kPlanMinPhotons);
    EXPECT_LE(10.0 * double(plan_passes(in).count) + 1000.0 * plan_passes(in).spp * 10.0, in.budget);
    // A budget that cannot hold even a pass of kPlanMinPhotons (20240) is no guide: N stays N0.
    in.budget = 20000.0;
    EXPECT_EQ(plan_passes(in).count, 100000);
}

TEST(PassPlan, SamplesTheUserLeftUnsetAreSizedToTheBudgetsShare) {
    // cornell_smoke with the march at a 2 s limit: 65536 pixels at 11400 units a sample, photons
    // 0.1 s. One sample per pixel fits the cap (1 s); the camera's noise wanted 8, 6 s of one core
    // in one pass, which the configured 16 samples (render.spp's default, not set) had allowed.
    PlanInputs in = inputs(/*v_camera*/ 1.0, /*v_half*/ 1e-6, /*v_quarter*/ -1.0, /*sample*/ 11400.0, /*photon*/ 1000.0);
    in.pixels = 65536.0;
    in.count = 100000;
    in.budget = 2.0 * kWorkUnitsPerSecond;
    const PassPlan p = plan_passes(in);
    EXPECT_EQ(p.spp, 1);
    EXPECT_LE(1000.0 * double(p.count) + in.pixels * p.spp * 11400.0, in.budget / kPlanMinPasses);
}

TEST(PassPlan, ThePilotsOneOffWorkIsTakenOffTheBudgetBeforeThePassesAreSized) {
    // A map whose bias dominates (it does not average over passes): the plan fills the cap
    // (budget / kPlanMinPasses) with photons, 4000 at 1 sample.
    PlanInputs in = inputs(/*v_camera*/ 1e-3, /*v_half*/ 1e-3, /*v_quarter*/ -1.0, /*sample*/ 10.0, /*photon*/ 100.0);
    in.candidates[0].bias2 = 1.0;
    in.budget = kPlanMinPasses * (100.0 * 4000.0 + 1000.0 * 1 * 10.0);
    auto cost = [&](const PassPlan& p) { return 100.0 * double(p.count) + 1000.0 * p.spp * 10.0; };
    const PassPlan whole = plan_passes(in);
    EXPECT_GT(cost(whole), (in.budget - in.budget / 8.0) / kPlanMinPasses);   // a pass that no longer fits twice
    // The pilot spent an eighth of the budget: the passes share the rest.
    in.pilot_work = in.budget / 8.0;
    EXPECT_EQ(plan_budget(in, true), in.budget - in.pilot_work);
    const PassPlan left = plan_passes(in);
    EXPECT_LE(cost(left), (in.budget - in.pilot_work) / kPlanMinPasses);
    EXPECT_LT(left.count, whole.count);
    // Its map's photon pass is one-off only where pass 0 does not reuse the map (N above the pilot's).
    in.pilot_count = 1000;
    in.pilot_map_work = in.budget / 4.0;
    EXPECT_EQ(plan_budget(in, true), in.budget - in.pilot_work);
    EXPECT_EQ(plan_budget(in, false), in.budget - in.pilot_work - in.pilot_map_work);
    const PassPlan more = plan_passes(in);
    EXPECT_LE(cost(more), (in.budget - in.pilot_work - (more.count > 1000 ? in.pilot_map_work : 0.0)) / kPlanMinPasses);
    // Without a budget nothing is taken off: the pilot's work changes no plan.
    PlanInputs free = inputs(/*v_camera*/ 1e-3, /*v_half*/ 1.0, /*v_quarter*/ 2.0, /*sample*/ 10.0, /*photon*/ 100.0);
    const PassPlan before = plan_passes(free);
    free.pilot_work = 1e12;
    EXPECT_EQ(plan_budget(free, true), 0.0);
    EXPECT_EQ(plan_passes(free).count, before.count);
    EXPECT_EQ(plan_passes(free).spp, before.spp);
}

TEST(PassPlan, APilotThatSpentTheWholeBudgetLeavesOnePassNoLargerThanTheConfigured) {
    PlanInputs in = inputs(/*v_camera*/ 1.0, /*v_half*/ 1e-3, /*v_quarter*/ -1.0, /*sample*/ 10.0, /*photon*/ 100.0);
    in.budget = 1e7;
    in.pilot_work = 2e7;
    EXPECT_EQ(plan_budget(in, true), 1.0);   // below every pass's cost
    const PassPlan p = plan_passes(in);
    EXPECT_LE(p.spp, in.spp);
    EXPECT_LE(p.count, in.count);
    // Scored as the one pass it is, over the time the run then takes (the pilot's and the pass's).
    const double cost = 100.0 * double(p.count) + 1000.0 * p.spp * 10.0;
    const double v = 1e-3 * (0.5 * 1000.0 / double(p.count)) + 1.0 / p.spp;
    EXPECT_NEAR(p.score[0], v * (in.budget - 1.0 + cost), 1e-9 * v * (in.budget + cost));
}
