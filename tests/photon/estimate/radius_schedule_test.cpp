// Progressive radii (photon/estimate/radius_schedule.h, docs/progressive.md): Knaus & Zwicker's
// measure ratio per pass, the kNN form's k and radius scale, and the scaled estimators' exactness on
// a uniform density (Monte Carlo with standard errors, fixed seeds).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cmath>
#include <vector>

#include "core/error.h"
#include "core/sampling/rng.h"
#include "photon/estimate/estimators.h"
#include "photon/estimate/radius_schedule.h"
#include "support/sample_statistics.h"

using namespace vpm;

TEST(RadiusSchedule, MeasureFollowsKnausZwickerRatio) {
    for (double alpha : {4.0 / 7.0, 2.0 / 3.0, 0.8}) {
        EXPECT_EQ(progressive_measure_ratio(0, alpha), 1.0);
        for (int64_t i : {0, 1, 2, 7, 63, 1000}) {
            // 1-based pass p = i + 1: V_{p+1} / V_p = (p + alpha) / (p + 1).
            const double p = double(i + 1);
            EXPECT_NEAR(progressive_measure_ratio(i + 1, alpha) / progressive_measure_ratio(i, alpha), (p + alpha) / (p + 1.0), 1e-10);
        }
        // The asymptote i^(alpha - 1) / Gamma(1 + alpha).
        const double i = 1e6;
        EXPECT_NEAR(progressive_measure_ratio(int64_t(i), alpha) * std::tgamma(1.0 + alpha) / std::pow(i, alpha - 1.0), 1.0, 1e-5);
    }
    EXPECT_EQ(progressive_measure_ratio(12345, 1.0), 1.0);
    EXPECT_NEAR(progressive_radius_scale(5, 0.5, 2), std::sqrt(progressive_measure_ratio(5, 0.5)), 1e-15);
    EXPECT_DOUBLE_EQ(optimal_progressive_alpha(3), 4.0 / 7.0);
    EXPECT_DOUBLE_EQ(optimal_progressive_alpha(2), 2.0 / 3.0);
    EXPECT_DOUBLE_EQ(optimal_progressive_alpha(1), 4.0 / 5.0);
    EXPECT_THROW(progressive_measure_ratio(-1, 0.5), Error);
    EXPECT_THROW(progressive_measure_ratio(1, 0.0), Error);
    EXPECT_THROW(progressive_radius_scale(1, 0.5, 4), Error);
}

TEST(RadiusSchedule, KnnPassShrinksKToTheFloorThenTheRadius) {
    const std::vector<ScheduledKernel> points = {{3, 4.0 / 7.0}};
    EXPECT_EQ(progressive_k(0, 32, 4, points), 32);
    EXPECT_EQ(progressive_knn_scale(0, 32, 32, points[0]), 1.0);
    int last_k = 32;
    for (int64_t i = 1; i < 4096; i = i * 3 / 2 + 1) {
        const int k = progressive_k(i, 32, 4, points);
        EXPECT_LE(k, last_k);
        EXPECT_GE(k, 4);
        last_k = k;
        const double s = progressive_knn_scale(i, 32, k, points[0]);
        EXPECT_LE(s, 1.0);
        // The leading-order bias s^2 Gamma(k-1+2/3)/Gamma(k-1) follows m_i^(2/3) exactly.
        const double target = std::pow(progressive_measure_ratio(i, 4.0 / 7.0), 2.0 / 3.0) * knn_bias_moment(32, 3);
        EXPECT_NEAR(s * s * knn_bias_moment(k, 3), target, 1e-12 * target);
        // k is the smallest that reaches the target with s <= 1.
        if (k > 4) {
            EXPECT_LT(knn_bias_moment(k - 1, 3), target);
        }
    }
    EXPECT_EQ(last_k, 4);
    EXPECT_LT(progressive_knn_scale(4000, 32, 4, points[0]), 0.75);   // below the floor the radius goes on shrinking
    // Two kernels: k serves both (the surface's target falls faster).
    const std::vector<ScheduledKernel> both = {{3, 4.0 / 7.0}, {2, 2.0 / 3.0}};
    const int k = progressive_k(10, 32, 4, both);
    EXPECT_GE(k, progressive_k(10, 32, 4, points));
    EXPECT_LE(progressive_knn_scale(10, 32, k, both[1]), 1.0);
    EXPECT_THROW(progressive_knn_scale(1, 32, 2, points[0]), Error);   // would need a ball beyond r_k
    // A k below the floor stays: only the radius shrinks.
    EXPECT_EQ(progressive_k(100, 3, 4, points), 3);
}

namespace {

// Unit-weight estimates at the centre of a unit cube holding n uniform points (density n), k-th
// neighbour, radius scale s; returns (corrected, classic) samples over `trials` maps.
struct Samples {
    test::Sample corrected, classic;
};
Samples uniform_estimates(int n, size_t k, double s, int trials, uint64_t seed) {
    Samples out;
    Rng rng(seed);
    std::vector<double> d2(static_cast<size_t>(n)), w(static_cast<size_t>(n), 1.0);
    const Estimator corrected = Estimator::named("corrected").with_radius_scale(s);
    const Estimator classic = Estimator::named("classic").with_radius_scale(s);
    for (int t = 0; t < trials; ++t) {
        for (int i = 0; i < n; ++i) {
            const double x = rng.uniform() - 0.5, y = rng.uniform() - 0.5, z = rng.uniform() - 0.5;
            d2[size_t(i)] = x * x + y * y + z * z;
        }
        std::partial_sort(d2.begin(), d2.begin() + long(k), d2.end());
        out.corrected.add(estimate_density<double>(corrected, w.data(), d2.data(), k, false, k, kInfinity, 3).value / n);
        out.classic.add(estimate_density<double>(classic, w.data(), d2.data(), k, false, k, kInfinity, 3).value / n);
    }
    return out;
}

}  // namespace

// With r = s r_k the corrected estimate counts the photons within r over V(r): unbiased for every k
// and s, with relative variance (n-1)/n ((1 - s^3)/s^3 + k - 1)/(k - 2) - 1 (docs/progressive.md);
// classic keeps its k-th photon's term, k/(k-1) high.
TEST(RadiusSchedule, ScaledCorrectedEstimateUnbiasedOnUniformDensity) {
    const int n = 2000;
    for (const auto& [k, s] : std::vector<std::pair<size_t, double>>{{4, 0.6}, {8, 0.8}, {16, 0.5}}) {
        const Samples m = uniform_estimates(n, k, s, 20000, 17 + k);
        const double kk = double(k), beta = s * s * s;
        EXPECT_NEAR(m.corrected.mean(), 1.0, 4.0 * m.corrected.se()) << "k " << k << " s " << s;
        EXPECT_NEAR(m.classic.mean(), kk / (kk - 1.0), 4.0 * m.classic.se()) << "k " << k << " s " << s;
        const double rel_var = double(n - 1) / n * ((1.0 - beta) / beta + kk - 1.0) / (kk - 2.0) - 1.0;
        // The sample variance's standard error is about var sqrt(2 / N) for these near-Gaussian
        // tails; 5 of them, and a test that a fixed radius scale of 1 would fail.
        // (k = 4: 1/V(r_k) has no fourth moment, so its sample variance has no standard error.)
        if (k > 4) {
            EXPECT_NEAR(m.corrected.var(), rel_var, 5.0 * rel_var * std::sqrt(2.0 / 20000.0) + 0.02 * rel_var) << "k " << k;
            EXPECT_GT(rel_var, 1.2 / (kk - 2.0));
        }
    }
    EXPECT_THROW(Estimator::named("corrected").with_radius_scale(1.5), Error);
    EXPECT_THROW(Estimator::named("corrected").with_radius_scale(0.0), Error);
}

// Rule (a) under the scale (count within s R over V(s R) where fewer than k photons lie within R)
// together with the scaled kNN estimate stays exact for a Poisson process (estimators.h).
TEST(RadiusSchedule, ScaledFixedRadiusRuleKeepsThePoissonSplitExact) {
    const size_t k = 6;
    const double R = 0.2, s = 0.7, mean_count = 4.0;   // P(N < k) about 0.2: both branches matter
    const double rho = mean_count / ball_volume(3, R);
    const Estimator e = Estimator::named("corrected").with_radius_scale(s);
    Rng rng(5);
    test::Sample est;
    std::vector<double> d2, w;
    int fixed = 0;
    for (int t = 0; t < 40000; ++t) {
        // Poisson count in B(R), positions uniform in it.
        int count = 0;
        for (double l = std::exp(-mean_count), p = rng.uniform(); p > l; p *= rng.uniform()) ++count;
        d2.clear();
        for (int i = 0; i < count; ++i) d2.push_back(R * R * std::pow(rng.uniform(), 2.0 / 3.0));
        std::sort(d2.begin(), d2.end());
        w.assign(d2.size(), 1.0);
        const Estimate<double> x = estimate_density<double>(e, w.data(), d2.data(), d2.size(), true, k, R, 3);
        fixed += x.kind == EstimateCase::fixed_radius || x.kind == EstimateCase::empty;
        est.add(x.value / rho);
    }
    EXPECT_GT(fixed, 4000);
    EXPECT_NEAR(est.mean(), 1.0, 4.0 * est.se());
}

// The half-space's first-collision density under normal incidence, lambda(z) ~ exp(-z) (closed
// form), at depth 3 (the balls stay inside the medium): the corrected estimate's smoothing bias,
// +Laplacian/(2(d+2)) s^2 E[r^2]-like = +s^2 r^2 / 10, follows the schedule, so the mean bias over
// passes 0..63 is progressive_bias_factor(0, 64, 4/7, 3) (0.445) times pass 0's, within standard
// errors (each pass a fresh Poisson sample; a fixed schedule would keep factor 1).
TEST(RadiusSchedule, HalfSpaceDensityBiasOfSixtyFourPassesFallsByThePredictedFactor) {
    const int passes = 64, k = 32, k_floor = 4;
    const double lambda0 = 22.0, half = 1.5;   // intensity at the query; the sampled box around it
    const std::vector<ScheduledKernel> points = {{3, optimal_progressive_alpha(3)}};
    // exp(-(z - 3)) on z - 3 in [-half, half]: its maximum e^half bounds the rejection.
    const double majorant = lambda0 * std::exp(half), volume = std::pow(2.0 * half, 3);
    Rng rng(44);
    std::vector<double> d2;
    std::vector<double> w;
    auto estimate = [&](int pass) {
        const int kp = progressive_k(pass, k, k_floor, points);
        const Estimator e = Estimator::named("corrected").with_radius_scale(progressive_knn_scale(pass, k, kp, points[0]));
        // majorant * volume uniform candidates thinned to the density (a binomial sample: the kNN
        // estimates' theory holds for any count).
        const int count = int(majorant * volume);
        d2.clear();
        for (int i = 0; i < count; ++i) {
            const double x = half * (2.0 * rng.uniform() - 1.0), y = half * (2.0 * rng.uniform() - 1.0),
                         z = half * (2.0 * rng.uniform() - 1.0);
            if (rng.uniform() * majorant < lambda0 * std::exp(-z)) d2.push_back(x * x + y * y + z * z);
        }
        std::partial_sort(d2.begin(), d2.begin() + kp, d2.end());
        w.assign(size_t(kp), 1.0);
        EXPECT_LT(d2[size_t(kp) - 1], half * half);   // the ball inside the sampled box
        return estimate_density<double>(e, w.data(), d2.data(), size_t(kp), false, size_t(kp), kInfinity, 3).value / lambda0 - 1.0;
    };
    test::Sample first, average;
    for (int t = 0; t < 6400; ++t) first.add(estimate(0));
    for (int t = 0; t < 64 * 150; ++t) average.add(estimate(t % passes));
    const double factor = progressive_bias_factor(0, passes, optimal_progressive_alpha(3), 3);
    const double se = std::sqrt(average.se() * average.se() + factor * factor * first.se() * first.se());
    std::printf("half-space density: pass 0 bias %+.4f +- %.4f, 64-pass mean %+.4f +- %.4f, predicted %+.4f\n", first.mean(),
                first.se(), average.mean(), average.se(), factor * first.mean());
    EXPECT_GT(first.mean(), 8.0 * first.se());
    EXPECT_NEAR(average.mean(), factor * first.mean(), 3.5 * se);
    EXPECT_LT(average.mean(), first.mean() - 4.0 * se);
}
