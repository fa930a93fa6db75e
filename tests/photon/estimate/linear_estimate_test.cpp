// photons.extinction = "linear" (photon/estimate/linear_estimate.h) never returns a negative
// radiance: at a flat lit boundary (the half-ball's closed-form sigma_t moments) a bright photon deep
// in the ball, where its linear weight h is negative, would make the corrected sum negative; the
// estimate falls back to the ball normalisation and counts it. Where the corrected sum is positive
// the estimate is the linear one, not the ball's, and nothing is counted.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/math.h"
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
