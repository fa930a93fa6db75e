// scene/media/ball_clip_moments.h (issue 21): the volume, first and second moments of a ball
// clipped by a box (inclusion-exclusion of caps, edges and corners) or by a ball (a lens).
#include <gtest/gtest.h>

#include <cmath>

#include "core/sampling/rng.h"
#include "scene/media/ball_clip_moments.h"
#include "scene/media/homogeneous_medium.h"

using namespace vpm;

namespace {

// The moments of B(0, r) ∩ region by the midpoint rule on an n^3 grid over the ball's cube: its
// error is that of the boundary cells, about 1e-4 of the ball's moments at n = 240 (tolerance 1e-3).
template <class Inside>
ClipMoments grid_moments(double r, int n, const Inside& inside) {
    ClipMoments m;
    const double h = 2.0 * r / n, w = h * h * h;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j)
            for (int k = 0; k < n; ++k) {
                const Vec3 u(-r + (i + 0.5) * h, -r + (j + 0.5) * h, -r + (k + 0.5) * h);
                if (u.squaredNorm() > r * r || !inside(u)) continue;
                m.m0 += w;
                m.m1 += w * u;
                m.m2 += w * (u * u.transpose());
            }
    return m;
}

void expect_close(const ClipMoments& a, const ClipMoments& b, double r, double tol, const char* what) {
    const double v = (4.0 / 3.0) * kPi * r * r * r;   // scale of each moment: v, v r, v r^2
    EXPECT_NEAR(a.m0, b.m0, tol * v) << what;
    EXPECT_LT((a.m1 - b.m1).norm(), tol * v * r) << what;
    EXPECT_LT((a.m2 - b.m2).norm(), tol * v * r * r) << what;
}

}  // namespace

TEST(BallClipMoments, WholeBallIsExactAndCentred) {
    ClipMoments m;
    ASSERT_TRUE(ball_box_moments(0.5, Vec3::Constant(-1.0), Vec3::Constant(1.0), m));
    EXPECT_DOUBLE_EQ(m.m0, 4.0 / 3.0 * kPi * 0.125);
    EXPECT_TRUE(m.m1.isZero(0.0)) << "the linear estimate's exact skip relies on an exactly zero offset";
    EXPECT_DOUBLE_EQ(m.m2(1, 1), 4.0 / 15.0 * kPi * std::pow(0.5, 5));
    EXPECT_EQ(m.m2(0, 1), 0.0);
    EXPECT_FALSE(ball_box_moments(0.5, Vec3(0.1, -1, -1), Vec3::Constant(1.0), m)) << "centre outside the box";
}

TEST(BallClipMoments, FacesEdgesAndCornersAgreeWithAGrid) {
    const double r = 1.0;
    struct Case {
        Vec3 lo, hi;
        const char* what;
    };
    for (const Case& c : {Case{Vec3(-0.3, -2, -2), Vec3(2, 2, 2), "one face"},
                          Case{Vec3(-0.3, -0.4, -2), Vec3(0.7, 2, 2), "an edge and the opposite face"},
                          Case{Vec3(-0.3, -0.2, -0.5), Vec3(2, 2, 2), "a corner"},
                          Case{Vec3(-0.01, -0.9, -0.3), Vec3(0.2, 0.02, 2), "a thin slab's corners, near tangent"},
                          Case{Vec3(-0.8, -0.75, -0.7), Vec3(0.6, 0.65, 0.7), "every face, edge and corner"}}) {
        ClipMoments m;
        ASSERT_TRUE(ball_box_moments(r, c.lo, c.hi, m)) << c.what;
        const ClipMoments g = grid_moments(r, 240, [&](const Vec3& u) { return (u.array() >= c.lo.array()).all() && (u.array() <= c.hi.array()).all(); });
        expect_close(m, g, r, 1e-3, c.what);
    }
}

// Two boxes sharing the plane through the centre add up to their union: an identity that holds
// exactly, so the edge and corner terms' quadrature must meet it to its own accuracy (1e-7 of the ball).
TEST(BallClipMoments, BoxesSplitThroughTheCentreAddUp) {
    Rng rng(2101, 0);
    double worst = 0.0;
    for (int it = 0; it < 3000; ++it) {
        const Vec3 lo(-1.2 * rng.uniform(), -1.2 * rng.uniform(), -1.2 * rng.uniform());
        const Vec3 hi(1.2 * rng.uniform(), 1.2 * rng.uniform(), 1.2 * rng.uniform());
        const int a = it % 3;
        Vec3 hi1 = hi, lo2 = lo;
        hi1[a] = 0.0;
        lo2[a] = 0.0;
        ClipMoments m, m1, m2;
        ASSERT_TRUE(ball_box_moments(1.0, lo, hi, m));
        ASSERT_TRUE(ball_box_moments(1.0, lo, hi1, m1));
        ASSERT_TRUE(ball_box_moments(1.0, lo2, hi, m2));
        worst = std::max({worst, std::abs(m.m0 - m1.m0 - m2.m0), (m.m1 - m1.m1 - m2.m1).norm(), (m.m2 - m1.m2 - m2.m2).norm()});
    }
    EXPECT_LT(worst, 1e-7 * 4.0 / 3.0 * kPi);
}

TEST(BallClipMoments, LensAgreesWithAGridAndTheSpheresVolume) {
    const double r = 1.0;
    for (const auto& [c, R] : {std::pair<Vec3, double>{Vec3(0.8, 0.3, -0.2), 0.9}, {Vec3(0.1, 0.2, 0.0), 0.5},
                               {Vec3(-1.2, 0.0, 0.5), 2.0}}) {
        const ClipMoments m = ball_ball_moments(r, c, R);
        const ClipMoments g = grid_moments(r, 240, [&](const Vec3& u) { return (u - c).squaredNorm() <= R * R; });
        expect_close(m, g, r, 1e-3, "lens");
        // The medium's volume closed form (issue 20) for the same lens.
        const HomogeneousMedium s = HomogeneousMedium::sphere(c, R, 1.0, Rgb::Constant(0.9), 0.0);
        double v = -1.0;
        ASSERT_TRUE(s.ball_integral(Vec3::Zero(), r, v));
        EXPECT_NEAR(m.m0, v, 1e-12);
    }
    EXPECT_EQ(ball_ball_moments(1.0, Vec3(3, 0, 0), 1.5).m0, 0.0);
}

// HomogeneousMedium::ball_moments is sigma_t times the geometry, about x.
TEST(BallClipMoments, HomogeneousMediumScalesBySigmaT) {
    const HomogeneousMedium b = HomogeneousMedium::box(Vec3(0, 0, 0), Vec3(1, 2, 3), 2.5, Rgb::Constant(0.9), 0.0);
    const Vec3 x(0.1, 0.15, 2.9);
    double m0 = 0;
    Vec3 m1;
    Eigen::Matrix3d m2;
    ASSERT_TRUE(b.ball_moments(x, 0.3, m0, m1, m2));
    ClipMoments g;
    ASSERT_TRUE(ball_box_moments(0.3, -x, Vec3(1, 2, 3) - x, g));
    EXPECT_DOUBLE_EQ(m0, 2.5 * g.m0);
    EXPECT_LT((m1 - 2.5 * g.m1).norm(), 1e-15);
    double v = -1.0;
    ASSERT_TRUE(b.ball_integral(x, 0.3, v)) << "a corner: now closed";
    EXPECT_DOUBLE_EQ(v, m0);
    EXPECT_GT(m1.x(), 0.0) << "the clipped ball's centroid lies inside, towards +x";
    EXPECT_FALSE(b.ball_moments(Vec3(-0.1, 1, 1.5), 0.3, m0, m1, m2)) << "x outside the box: the caller integrates";
}
