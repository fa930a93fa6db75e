// sincos_turns: sin and cos of 2 pi u against long-double libm, exact values at the quarter
// turns, and the unit circle, over the samplers' range u in [0, 1) and beyond.
#include <gtest/gtest.h>

#include <cmath>

#include "core/sampling/rng.h"
#include "core/sampling/turn_sincos.h"

using namespace vpm;

namespace {

constexpr long double kTwoPiL = 6.283185307179586476925286766559005768L;

TEST(TurnSinCos, WithinAFewUlpsOfLongDoubleLibm) {
    Rng rng(3, 0);
    double worst_s = 0.0, worst_c = 0.0;
    for (int i = 0; i < 200000; ++i) {
        const double u = i < 1000 ? i / 1000.0 : (i < 2000 ? 1.0 - (i - 999) * 0x1p-53 : rng.uniform());
        const SinCos r = sincos_turns(u);
        const long double a = kTwoPiL * u;
        worst_s = std::max(worst_s, double(std::fabs(r.sin - std::sin(a))));
        worst_c = std::max(worst_c, double(std::fabs(r.cos - std::cos(a))));
    }
    // Values are at most 1 in magnitude: 4 ulps of 1 is 8.9e-16.
    EXPECT_LE(worst_s, 4 * 0x1p-52);
    EXPECT_LE(worst_c, 4 * 0x1p-52);
}

TEST(TurnSinCos, QuarterTurnsAreExact) {
    const double u[] = {0.0, 0.25, 0.5, 0.75, 1.0, -0.25, 2.5};
    const double s[] = {0.0, 1.0, 0.0, -1.0, 0.0, -1.0, 0.0};
    const double c[] = {1.0, 0.0, -1.0, 0.0, 1.0, 0.0, -1.0};
    for (int i = 0; i < 7; ++i) {
        const SinCos r = sincos_turns(u[i]);
        EXPECT_EQ(r.sin, s[i]) << "u = " << u[i];
        EXPECT_EQ(r.cos, c[i]) << "u = " << u[i];
    }
}

TEST(TurnSinCos, OnTheUnitCircleAndInTheRightQuadrant) {
    Rng rng(5, 0);
    for (int i = 0; i < 100000; ++i) {
        const double u = 8.0 * rng.uniform() - 4.0;
        const SinCos r = sincos_turns(u);
        EXPECT_NEAR(r.sin * r.sin + r.cos * r.cos, 1.0, 4e-16);
        const double f = u - std::floor(u);   // quadrant of the angle from the fraction of a turn
        EXPECT_TRUE(f < 0.5 ? r.sin >= 0.0 : r.sin <= 0.0) << u;
        EXPECT_TRUE((f < 0.25 || f > 0.75) ? r.cos >= 0.0 : r.cos <= 0.0) << u;
    }
}

}  // namespace
