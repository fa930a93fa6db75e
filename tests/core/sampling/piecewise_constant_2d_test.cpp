// The piecewise-constant 2D distribution: probabilities sum to 1, zero cells and rows are never
// drawn, samples land in their cell, and their histogram matches the probabilities (chi-square).
#include <gtest/gtest.h>

#include "core/error.h"
#include "core/sampling/piecewise_constant_2d.h"
#include "core/sampling/rng.h"

#include "support/chi_square.h"

using namespace vpm;

namespace {

// 7 columns x 5 rows: row 2 all zero, a few zero cells elsewhere (first, last, middle).
std::vector<double> test_weights() {
    std::vector<double> w(35);
    for (int r = 0; r < 5; ++r)
        for (int c = 0; c < 7; ++c) w[r * 7 + c] = r == 2 ? 0.0 : 0.5 + ((c * 5 + r * 3) % 7);
    w[0] = 0.0;
    w[6] = 0.0;
    w[3 * 7 + 3] = 0.0;
    w[4 * 7 + 6] = 0.0;
    return w;
}

}  // namespace

TEST(PiecewiseConstant2D, ProbabilitiesSumToOneAndFollowTheWeights) {
    const std::vector<double> w = test_weights();
    const PiecewiseConstant2D d(7, 5, w);
    double total = 0.0, sum = 0.0;
    for (double x : w) total += x;
    for (int r = 0; r < 5; ++r)
        for (int c = 0; c < 7; ++c) {
            sum += d.probability(c, r);
            EXPECT_NEAR(d.probability(c, r), w[r * 7 + c] / total, 1e-15);
            EXPECT_NEAR(d.density(c, r), d.probability(c, r) * 35.0, 1e-14);
        }
    EXPECT_NEAR(sum, 1.0, 1e-14);
    EXPECT_DOUBLE_EQ(d.total(), total);
    EXPECT_FALSE(d.empty());
}

TEST(PiecewiseConstant2D, SampleHistogramPassesChiSquareAndNeverHitsZeroCells) {
    const std::vector<double> w = test_weights();
    const PiecewiseConstant2D d(7, 5, w);
    Rng rng(2024, 7);
    const int n = 200000;
    std::vector<double> observed(35, 0.0), expected(35, 0.0);
    for (int i = 0; i < n; ++i) {
        const auto s = d.sample(rng.uniform(), rng.uniform());
        ASSERT_GT(w[s.row * 7 + s.column], 0.0) << "a zero-weight cell was sampled";
        ASSERT_EQ(int(s.u * 7), s.column);   // the continuous position lies in the cell
        ASSERT_EQ(int(s.v * 5), s.row);
        ASSERT_EQ(s.probability, d.probability(s.column, s.row));
        observed[s.row * 7 + s.column] += 1.0;
    }
    for (int k = 0; k < 35; ++k) expected[k] = n * d.probability(k % 7, k / 7);
    const test::ChiSquare good = test::chi_square(observed, expected);
    EXPECT_GT(good.p, 1e-3) << "chi2 " << good.statistic << " dof " << good.dof;
    // Power: the same samples against uniform probabilities over the non-zero cells must fail.
    std::vector<double> wrong(35, 0.0);
    for (int k = 0; k < 35; ++k) wrong[k] = w[k] > 0.0 ? n / 26.0 : 0.0;
    EXPECT_LT(test::chi_square(observed, wrong).p, 1e-3);
}

TEST(PiecewiseConstant2D, AllZeroIsEmptyAndNegativeOrNanIsAnError) {
    const PiecewiseConstant2D d(4, 3, std::vector<double>(12, 0.0));
    EXPECT_TRUE(d.empty());
    EXPECT_EQ(d.probability(1, 1), 0.0);
    const auto s = d.sample(0.7, 0.3);   // a valid cell, even so
    EXPECT_GE(s.column, 0);
    EXPECT_LT(s.column, 4);
    EXPECT_GE(s.row, 0);
    EXPECT_LT(s.row, 3);
    std::vector<double> bad(12, 1.0);
    bad[5] = -1.0;
    EXPECT_THROW(PiecewiseConstant2D(4, 3, bad), Error);
    bad[5] = std::nan("");
    EXPECT_THROW(PiecewiseConstant2D(4, 3, bad), Error);
    EXPECT_THROW(PiecewiseConstant2D(4, 3, std::vector<double>(11, 1.0)), Error);
}

TEST(ChiSquareSupport, PValuesMatchKnownQuantiles) {
    // chi-square quantiles at p = 0.001: 6 dof 22.458, 100 dof 149.449; p = 0.5 at 1 dof: 0.45494.
    EXPECT_NEAR(test::gamma_q(3.0, 22.458 / 2), 1e-3, 1e-6);
    EXPECT_NEAR(test::gamma_q(50.0, 149.449 / 2), 1e-3, 1e-6);
    EXPECT_NEAR(test::gamma_q(0.5, 0.45494 / 2), 0.5, 1e-5);
}
