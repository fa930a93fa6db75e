#include <gtest/gtest.h>

#include <cmath>

#include "core/sampling/rng.h"

using namespace vpm;

TEST(Rng, SameSeedAndStreamRepeat) {
    Rng a(1, 2), b(1, 2);
    for (int i = 0; i < 100; ++i) EXPECT_EQ(a.next_u32(), b.next_u32());
}

TEST(Rng, StreamsDiffer) {
    Rng a(1, 2), b(1, 3), c(2, 2);
    int same_b = 0, same_c = 0;
    for (int i = 0; i < 1000; ++i) {
        const uint32_t x = a.next_u32();
        same_b += x == b.next_u32();
        same_c += x == c.next_u32();
    }
    EXPECT_LT(same_b, 3);
    EXPECT_LT(same_c, 3);
}

TEST(Rng, UniformMomentsAndRange) {
    Rng rng(9, 0);
    const int n = 1000000;
    double sum = 0.0, sum2 = 0.0;
    for (int i = 0; i < n; ++i) {
        const double u = rng.uniform();
        ASSERT_TRUE(u >= 0.0 && u < 1.0);
        sum += u;
        sum2 += u * u;
    }
    // mean 1/2 (sd of the mean sqrt(1/12/n)), second moment 1/3.
    EXPECT_NEAR(sum / n, 0.5, 3.0 * std::sqrt(1.0 / 12.0 / n));
    EXPECT_NEAR(sum2 / n, 1.0 / 3.0, 3.0 * std::sqrt(4.0 / 45.0 / n));
}

TEST(Rng, UniformIndexIsUnbiased) {
    Rng rng(4, 4);
    const uint32_t n = 7;
    const int draws = 700000;
    int counts[7] = {};
    for (int i = 0; i < draws; ++i) {
        const uint32_t k = rng.uniform_index(n);
        ASSERT_LT(k, n);
        ++counts[k];
    }
    double chi2 = 0.0;
    for (int c : counts) chi2 += (c - draws / 7.0) * (c - draws / 7.0) / (draws / 7.0);
    EXPECT_LT(chi2, 22.46);   // chi-square, 6 dof, p = 0.001
}
