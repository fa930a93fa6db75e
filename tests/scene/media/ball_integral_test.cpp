// Medium::ball_integral (issue 20): the closed forms photons.extinction = "ball" uses instead of a
// quadrature, against a 2^18-point Monte Carlo integral over the ball (relative standard error
// below 0.3% here; tolerance 5 standard errors).
#include <gtest/gtest.h>

#include <cmath>

#include "core/density_grid.h"
#include "core/sampling/rng.h"
#include "core/sampling/sampling.h"
#include "scene/media/grid_medium.h"
#include "scene/media/homogeneous_medium.h"

using namespace vpm;

namespace {

struct Mc {
    double mean, se;   // of the integral
};

Mc monte_carlo(const Medium& m, const Vec3& x, double r) {
    Rng rng(11, 0);
    const int n = 1 << 18;
    double s = 0, s2 = 0;
    const double v = (4.0 / 3.0) * kPi * r * r * r;
    for (int i = 0; i < n; ++i) {
        const double f = m.sigma_t(x + r * sample_uniform_ball(rng.uniform(), rng.uniform(), rng.uniform())) * v;
        s += f;
        s2 += f * f;
    }
    const double mean = s / n;
    return {mean, std::sqrt(std::max(0.0, s2 / n - mean * mean) / n)};
}

void expect_exact(const Medium& m, const Vec3& x, double r, const char* what) {
    double exact = -1.0;
    ASSERT_TRUE(m.ball_integral(x, r, exact)) << what;
    const Mc mc = monte_carlo(m, x, r);
    EXPECT_NEAR(exact, mc.mean, 5.0 * mc.se + 1e-9 * std::abs(mc.mean)) << what;   // 1e-9: rounding where sigma_t is constant
}

}  // namespace

TEST(BallIntegral, HomogeneousSphereLensInsideAndAround) {
    const HomogeneousMedium s = HomogeneousMedium::sphere(Vec3(1, 2, 3), 0.5, 3.0, Rgb::Constant(0.9), 0.0);
    expect_exact(s, Vec3(1.1, 2.0, 3.0), 0.2, "inside");
    expect_exact(s, Vec3(1.4, 2.1, 3.0), 0.3, "lens");
    expect_exact(s, Vec3(1.0, 2.0, 3.6), 0.9, "lens, ball larger than the sphere");
    expect_exact(s, Vec3(1.0, 2.0, 3.1), 2.0, "sphere inside the ball");
    double v = -1;
    ASSERT_TRUE(s.ball_integral(Vec3(3, 2, 3), 0.5, v));
    EXPECT_EQ(v, 0.0);
}

TEST(BallIntegral, HomogeneousBoxCapsEdgesAndCorners) {
    const HomogeneousMedium b = HomogeneousMedium::box(Vec3(0, 0, 0), Vec3(1, 2, 3), 2.0, Rgb::Constant(0.9), 0.0);
    expect_exact(b, Vec3(0.5, 1.0, 1.5), 0.3, "inside");
    expect_exact(b, Vec3(0.1, 1.0, 1.5), 0.3, "one face");
    expect_exact(b, Vec3(-0.2, 1.0, 1.5), 0.3, "centre outside, one face");
    expect_exact(b, Vec3(0.5, 1.0, 1.5), 0.7, "both faces of x");
    double v = -1;
    expect_exact(b, Vec3(0.1, 0.1, 1.5), 0.3, "an edge: caps of two axes overlap (issue 21: inclusion-exclusion)");
    expect_exact(b, Vec3(0.1, 1.9, 2.8), 0.35, "a corner");
    EXPECT_FALSE(b.ball_integral(Vec3(-0.1, 0.1, 1.5), 0.3, v)) << "an edge with the centre outside: not closed";
}

TEST(BallIntegral, GridBallInsideOneTrilinearCellIsItsCentreValue) {
    DensityGrid grid(Vec3i(0, 0, 0), Vec3i(15, 15, 15));
    Rng rng(3, 0);
    for (int z = 0; z < 16; ++z)
        for (int y = 0; y < 16; ++y)
            for (int x = 0; x < 16; ++x) grid.set_voxel(Vec3i(x, y, z), float(rng.uniform()));
    grid.finalize();
    Eigen::Affine3d t = Eigen::Affine3d::Identity();
    t.translate(Vec3(5, -1, 2));
    t.scale(Vec3(0.1, 0.2, 0.05));   // anisotropic, axis-aligned: an ellipsoid in index space
    const GridMedium m(std::move(grid), 7.0, Rgb::Constant(0.9), 0.0, t);
    const Vec3 x = t * Vec3(6.4, 7.55, 3.3);   // index cell [6,7] x [7,8] x [3,4]
    expect_exact(m, x, 0.01, "one cell");   // index half extents 0.1, 0.05, 0.2
    double v = -1;
    EXPECT_FALSE(m.ball_integral(x, 0.05, v)) << "the ball reaches the next cell";
    Eigen::Affine3d rotated = t;
    rotated.rotate(Eigen::AngleAxisd(0.3, Vec3(0, 0, 1)));
    DensityGrid g2(Vec3i(0, 0, 0), Vec3i(7, 7, 7));
    g2.set_voxel(Vec3i(3, 3, 3), 1.0f);
    g2.finalize();
    const GridMedium r(std::move(g2), 1.0, Rgb::Constant(0.9), 0.0, rotated);
    EXPECT_FALSE(r.ball_integral(rotated * Vec3(3.5, 3.5, 3.5), 1e-4, v)) << "rotated index axes: no closed form";
}
