// The study's walks scenario (analysis/study/walk_trial.h): every estimator within 4 standard errors of its
// derivation (docs/walk_correlation.md), the same numbers on any thread count, and its option checks.
#include <gtest/gtest.h>

#include <tbb/global_control.h>

#include <cmath>

#include "analysis/study/study.h"
#include "analysis/study/walk_trial.h"
#include "core/error.h"

using namespace vpm;

namespace {

StudyOptions walks_options(size_t trials) {
    StudyOptions o;
    o.scenarios = {StudyScenario::walks};
    o.dims = {3};
    o.ks = {8, 32};
    o.trials = trials;
    o.seed = 56;
    o.walks_per_trial = 512;
    o.walk_media = {WalkMedium{0.5, 0.0}};
    return o;
}

}  // namespace

// 3000 independent trials (8 queries each) at albedo 0.5: the walk-corrected and leave-group-out
// means are exact (0), walk_classic exact from the walks entering a ball, classic and corrected first
// order in the clustering.
TEST(StudyWalks, EveryEstimatorWithinFourStandardErrorsOfItsDerivation) {
    const StudyResult r = run_estimator_study(walks_options(3000));
    ASSERT_EQ(r.rows.size(), 2u * walk_study_methods().size());
    for (const StudyRow& row : r.rows) {
        EXPECT_EQ(row.scenario, "walks/a0.5/g0");
        ASSERT_TRUE(row.has_theory);
        EXPECT_EQ(row.trials, 3000u);
        EXPECT_NEAR(row.mean_error, row.th_error, 4.0 * row.se_mean)
            << study_row_label(row) << " k " << row.k << ": " << row.mean_error << " +- " << row.se_mean << ", theory "
            << row.th_error;
    }
    const std::string csv = study_csv(r);
    EXPECT_NE(csv.find("walks/a0.5/g0,3,8,walk_corrected,"), std::string::npos);
    EXPECT_NE(csv.find("walks/a0.5/g0,3,32,leave_group_out,"), std::string::npos);
}

// walk_classic's theory, int P(Poisson(m / c) >= k) dm / m^2, on a constant c: independent photons
// (c = 1) give the seed's 1/(k-1), walks that enter with c photons each 1/(c (k-1)) (substitute
// mu = m / c); the quadrature must reproduce both.
TEST(StudyWalks, WalkClassicTheoryOnAConstantEntryCount) {
    const double density = 40.0;
    for (const double entering : {1.0, 2.0, 3.5}) {
        WalkClustering c;
        for (size_t i = 0; i < 400; ++i) {
            c.radius.push_back(1e-3 * std::pow(5e3, double(i) / 399.0));   // 1e-3 .. 5 mfp
            c.s.push_back(0.0);
            c.c.push_back(entering);
        }
        for (const size_t k : {2, 3, 8, 32}) {
            const double expected = 1.0 / (entering * double(k - 1));
            EXPECT_NEAR(walk_theory_error(2, k, density, c), expected, 1e-6 * expected) << "c " << entering << " k " << k;
        }
    }
}

TEST(StudyWalks, SameNumbersOnAnyThreadCount) {
    StudyResult one, two;
    {
        tbb::global_control gc(tbb::global_control::max_allowed_parallelism, 1);
        one = run_estimator_study(walks_options(40));
    }
    {
        tbb::global_control gc(tbb::global_control::max_allowed_parallelism, 2);
        two = run_estimator_study(walks_options(40));
    }
    ASSERT_EQ(one.rows.size(), two.rows.size());
    for (size_t i = 0; i < one.rows.size(); ++i) {
        EXPECT_EQ(one.rows[i].mean_error, two.rows[i].mean_error) << i;
        EXPECT_EQ(one.rows[i].rel_variance, two.rows[i].rel_variance) << i;
    }
}

TEST(StudyWalks, TooFewWalksPerTrialIsOneClearError) {
    StudyOptions o = walks_options(10);
    o.walks_per_trial = 16 * 32 - 1;
    try {
        validate_study_options(o);
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("at least 16 x the largest k (512)"), std::string::npos) << e.what();
    }
    o = walks_options(10);
    o.walk_media = {WalkMedium{1.0, 0.0}};
    EXPECT_THROW(validate_study_options(o), Error);
}
