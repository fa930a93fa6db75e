// Henyey-Greenstein: normalisation, sampling distribution = evaluation, mean cosine = g,
// and stability at g = 0 and |g| -> 1.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "core/henyey_greenstein.h"
#include "core/sampling/rng.h"

using namespace vpm;

namespace {

// Closed-form CDF of the HG cosine, independent of the sampler's inversion formula.
double hg_cdf(double mu, double g) {
    if (g == 0.0) return 0.5 * (mu + 1.0);
    return (1.0 - g * g) / (2.0 * g) * (1.0 / std::sqrt(1.0 + g * g - 2.0 * g * mu) - 1.0 / (1.0 + g));
}

// Integral over the sphere, 2 pi int_{-1}^{1} p(mu) dmu, by composite Simpson in the variable
// x = log(1 + eps - s mu), s = sign(g), which resolves the peak for |g| near 1.
double hg_integral(double g) {
    const double s = g < 0.0 ? -1.0 : 1.0;
    const double eps = 1e-12;
    const double a = std::log(eps), b = std::log(2.0 + eps);
    const int n = 200000;
    const double h = (b - a) / n;
    double sum = 0.0;
    for (int i = 0; i <= n; ++i) {
        const double x = a + i * h;
        const double mu = 1.0 + eps - std::exp(x);
        const double f = 2.0 * kPi * hg_eval(s * mu, g) * std::exp(x);   // dmu = -e^x dx
        sum += f * (i == 0 || i == n ? 1.0 : (i % 2 ? 4.0 : 2.0));
    }
    return sum * h / 3.0;
}

class HgTest : public ::testing::TestWithParam<double> {};

}  // namespace

TEST_P(HgTest, IntegratesToOne) {
    EXPECT_NEAR(hg_integral(GetParam()), 1.0, 1e-6);
}

TEST_P(HgTest, SampledCosinesFollowTheEvaluatedDensity) {
    // Kolmogorov-Smirnov against the closed-form CDF; critical value at alpha = 1e-3.
    const double g = GetParam();
    const int n = 200000;
    std::vector<double> mu(n);
    Rng rng(42, 7);
    for (double& m : mu) m = hg_sample_cos(g, rng.uniform());
    std::sort(mu.begin(), mu.end());
    double d = 0.0;
    for (int i = 0; i < n; ++i) {
        const double f = hg_cdf(mu[i], g);
        d = std::max({d, std::abs(f - double(i) / n), std::abs(f - double(i + 1) / n)});
    }
    EXPECT_LT(d, 1.95 / std::sqrt(double(n))) << "g = " << g;
}

TEST_P(HgTest, MeanCosineEqualsG) {
    const double g = GetParam();
    const int n = 400000;
    Rng rng(3, 11);
    const Vec3 d_in = Vec3(0.3, -0.5, 0.8).normalized();
    double sum = 0.0, sum2 = 0.0;
    for (int i = 0; i < n; ++i) {
        const double u1 = rng.uniform(), u2 = rng.uniform();
        const Vec3 d_out = hg_sample(d_in, g, u1, u2);
        ASSERT_NEAR(d_out.norm(), 1.0, 1e-12);
        const double c = d_out.dot(d_in);
        sum += c;
        sum2 += c * c;
    }
    const double mean = sum / n;
    const double se = std::sqrt(std::max(1e-30, sum2 / n - mean * mean) / n);
    EXPECT_NEAR(mean, g, 3.0 * se + 1e-12) << "g = " << g;
}

INSTANTIATE_TEST_SUITE_P(GValues, HgTest, ::testing::Values(-0.99, -0.5, 0.0, 0.5, 0.99));

TEST(Hg, StableNearTheLimits) {
    Rng rng(5, 5);
    for (double g : {1e-9, -1e-9, 1e-6, 0.999999, -0.999999}) {
        for (int i = 0; i < 10000; ++i) {
            const double mu = hg_sample_cos(g, rng.uniform());
            ASSERT_TRUE(mu >= -1.0 && mu <= 1.0) << g;
            const double p = hg_eval(mu, g);
            ASSERT_TRUE(std::isfinite(p) && p >= 0.0) << g << " " << mu;
        }
    }
    // The forward peak of g = 0.999999 is (1+g)/(4 pi (1-g)^2): evaluated without cancellation.
    const double g = 0.999999;
    EXPECT_NEAR(hg_eval(1.0, g) / ((1.0 + g) / (4.0 * kPi * (1.0 - g) * (1.0 - g))), 1.0, 1e-9);
    EXPECT_NEAR(hg_eval(0.3, 0.0), 1.0 / (4.0 * kPi), 1e-15);
}
