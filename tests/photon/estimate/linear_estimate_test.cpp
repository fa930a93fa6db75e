// photons.extinction = "linear" (photon/estimate/linear_estimate.h) never returns a negative
// radiance: at a flat lit boundary (the half-ball's closed-form sigma_t moments) a bright photon deep
// in the ball, where its linear weight h is negative, would make the corrected sum negative; the
// estimate falls back to the ball normalisation and counts it. Where the corrected sum is positive
// the estimate is the linear one, not the ball's, and nothing is counted.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <vector>

#include "core/math.h"
#include "core/sampling/rng.h"
#include "photon/estimate/estimators.h"
#include "photon/estimate/linear_estimate.h"
#include "photon/map/photon_map.h"

using namespace vpm;

namespace {

// sigma_t = 1 in z > 0, the query at the origin: the moments of the half-ball of radius r.
BallMoments half_ball(double r) {
    BallMoments m;
    m.m0 = (2.0 / 3.0) * kPi * r * r * r;
    m.offset = Vec3(0.0, 0.0, 3.0 * r / 8.0);
    m.cov = Eigen::Matrix3d::Zero();
    m.cov(0, 0) = m.cov(1, 1) = r * r / 5.0;
    m.cov(2, 2) = r * r / 5.0 - 9.0 * r * r / 64.0;
    return m;
}

struct Linear {
    Rgb value, ball;
    uint64_t fallbacks = 0;
};

// Eight photons in the half-ball (k = 8 neighbours: r_k the farthest), powers as given.
Linear estimate(const std::vector<PhotonInput>& photons) {
    const PhotonMap map(photons);
    GatherBuffers buf;
    const Vec3 x = Vec3::Zero(), w_o = Vec3::UnitZ();
    const Estimator e = Estimator::named("corrected");
    const Estimate<Rgb> s = estimate_in_scattering(map, x, w_o, 0.0, e, photons.size(), kInfinity, buf);
    EXPECT_EQ(s.kind, EstimateCase::knn);
    const BallMoments m = half_ball(s.radius);
    std::vector<Rgb> scratch;
    Linear out;
    out.value = linear_estimate(s, e, buf, map, x, m, scratch, &out.fallbacks);
    out.ball = s.value / (m.m0 / ball_volume(3, s.radius));
    return out;
}

std::vector<PhotonInput> photons_with_deep_power(double deep_power) {
    std::vector<PhotonInput> in;
    const double shallow[7][3] = {{0.3, 0.0, 0.05}, {-0.3, 0.1, 0.1}, {0.0, 0.4, 0.05}, {0.1, -0.4, 0.1},
                                  {0.5, 0.2, 0.15}, {-0.2, -0.5, 0.1}, {0.0, 0.0, 0.2}};
    for (const auto& p : shallow) in.push_back({Vec3(p[0], p[1], p[2]), Vec3::UnitZ(), Rgb::Constant(1.0)});
    in.push_back({Vec3(0.0, 0.05, 0.95), Vec3::UnitZ(), Rgb::Constant(deep_power)});   // the farthest: r_k
    return in;
}

}  // namespace

TEST(LinearEstimate, ABrightPhotonDeepInTheBallFallsBackToTheBallNormalisation) {
    // The deep photon is the k-th (its power is not in the corrected sum), so put a second one deep.
    std::vector<PhotonInput> in = photons_with_deep_power(1.0);
    in[6] = {Vec3(0.05, 0.0, 0.9), Vec3::UnitZ(), Rgb::Constant(1000.0)};
    const Linear l = estimate(in);
    EXPECT_EQ(l.fallbacks, 1u);
    EXPECT_GT(l.ball.minCoeff(), 0.0);
    EXPECT_TRUE((l.value == l.ball).all());
}

TEST(LinearEstimate, APositiveCorrectedSumIsKeptAndNotCounted) {
    const Linear l = estimate(photons_with_deep_power(1.0));
    EXPECT_EQ(l.fallbacks, 0u);
    EXPECT_GT(l.value.minCoeff(), 0.0);
    // Shallow photons carry h > 1: the linear estimate reads above the ball's.
    EXPECT_GT(l.value[0], 1.5 * l.ball[0]);
}

// photons.extinction = "linear_signed": the same estimate without the fallback. At the lit face of a
// half-space of constant density (the query on the face: the half ball's closed-form moments) the
// ball normalisation is exact, and so is the linear one in the mean; the fallback raises it by
// E[(ball - linear) 1{linear < 0}]. Over independent Poisson point sets at k 4: linear_signed's mean
// equals the ball's within 3 SE, and linear - linear_signed (non-zero only where one fell back) is
// positive by many SE.
TEST(LinearSigned, KeepsTheNegativeEstimatesTheFallbackReplaces) {
    const std::vector<PhotonInput> deep = [] {
        std::vector<PhotonInput> in = photons_with_deep_power(1.0);
        in[6] = {Vec3(0.05, 0.0, 0.9), Vec3::UnitZ(), Rgb::Constant(1000.0)};
        return in;
    }();
    {
        const PhotonMap map(deep);
        GatherBuffers buf;
        const Estimator e = Estimator::named("corrected");
        const Estimate<Rgb> s = estimate_in_scattering(map, Vec3::Zero(), Vec3::UnitZ(), 0.0, e, deep.size(), kInfinity, buf);
        std::vector<Rgb> scratch;
        uint64_t negatives = 0;
        const Rgb kept = linear_estimate(s, e, buf, map, Vec3::Zero(), half_ball(s.radius), scratch, &negatives, true);
        EXPECT_EQ(negatives, 1u);
        EXPECT_LT(kept.maxCoeff(), 0.0);
    }
    const double density = 400.0, R = 0.45;   // about 76 points in the half ball; r_4 ~ 0.17
    const int sets = 40000;
    const Estimator e = Estimator::named("corrected");
    Rng rng(47, 0);
    double sum_signed_minus_ball = 0, sq_signed_minus_ball = 0, sum_fallback_gain = 0, sq_fallback_gain = 0, sum_ball = 0;
    uint64_t fallbacks = 0;
    for (int t = 0; t < sets; ++t) {
        // A Poisson count of uniform points in the half ball z > 0 of radius R (by rejection from the box).
        const double mean_count = density * 2.0 / 3.0 * kPi * R * R * R;
        int n = 0;
        for (double l = -std::log(1.0 - rng.uniform()); l < mean_count; l += -std::log(1.0 - rng.uniform())) ++n;
        std::vector<PhotonInput> in;
        while (int(in.size()) < n) {
            const Vec3 p(R * (2.0 * rng.uniform() - 1.0), R * (2.0 * rng.uniform() - 1.0), R * rng.uniform());
            if (p.squaredNorm() < R * R) in.push_back({p, Vec3::UnitZ(), Rgb::Constant(1.0)});
        }
        if (in.size() < 5) continue;
        const PhotonMap map(in);
        GatherBuffers buf;
        const Estimate<Rgb> s = estimate_in_scattering(map, Vec3::Zero(), Vec3::UnitZ(), 0.0, e, 4, kInfinity, buf);
        ASSERT_LT(s.radius, R);
        const BallMoments m = half_ball(s.radius);
        std::vector<Rgb> scratch;
        const double ball = s.value[0] / (m.m0 / ball_volume(3, s.radius));
        const double linear = linear_estimate(s, e, buf, map, Vec3::Zero(), m, scratch, &fallbacks)[0];
        const double kept = linear_estimate(s, e, buf, map, Vec3::Zero(), m, scratch, nullptr, true)[0];
        sum_ball += ball;
        sum_signed_minus_ball += kept - ball;
        sq_signed_minus_ball += (kept - ball) * (kept - ball);
        sum_fallback_gain += linear - kept;
        sq_fallback_gain += (linear - kept) * (linear - kept);
    }
    const double N = sets, mean_ball = sum_ball / N;
    // The ball's mean is the density's estimate: density / (4 pi) per unit sigma_t (g = 0 phase).
    const double d = sum_signed_minus_ball / N, d_se = std::sqrt((sq_signed_minus_ball / N - d * d) / (N - 1.0));
    const double f = sum_fallback_gain / N, f_se = std::sqrt((sq_fallback_gain / N - f * f) / (N - 1.0));
    EXPECT_GT(fallbacks, 0u);
    EXPECT_LT(std::abs(d), 3.0 * d_se) << "linear_signed - ball " << d / mean_ball << " +- " << d_se / mean_ball;
    EXPECT_GT(f, 5.0 * f_se) << "fallback gain " << f / mean_ball << " +- " << f_se / mean_ball;
    std::cout << "linear_signed - ball " << 100.0 * d / mean_ball << "% +- " << 100.0 * d_se / mean_ball
              << "%; fallback gain " << 100.0 * f / mean_ball << "% +- " << 100.0 * f_se / mean_ball << "%, "
              << fallbacks << " fallbacks in " << sets << " sets\n";
}
