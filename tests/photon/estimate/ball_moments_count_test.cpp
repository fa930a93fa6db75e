// The ball moments' counted work (photons.extinction = "linear", the default): BallExtinction::moments
// reports the sigma_t lookups and lattice visits it makes, as integral() does, so that the plan's cost
// model (render/plan/work_units.h) sees them. Uncounted, the march was charged 0.56-0.62x its CPU per
// sample in the thin blob, where the lattice's moments were a third of its render (docs/studies/march.md section 22).
#include <gtest/gtest.h>

#include <memory>
#include <vector>

#include "io/vdb_io.h"
#include "photon/estimate/ball_extinction.h"
#include "photon/estimate/mass_lattice.h"
#include "scene/media/grid_medium.h"
#include "scene/media/homogeneous_medium.h"
#include "support/repo_media.h"

using namespace vpm;

namespace {

using vpm::test::repo_grid_medium;

}  // namespace

TEST(BallMomentsCount, SmallBallCountsTheFifteenPointRule) {
    const auto media = repo_grid_medium("blob");
    const BallExtinction ball(media);
    const Bounds3 box = media[0]->bounds();
    const Vec3 x = 0.5 * (box.lo + box.hi), size = box.hi - box.lo;
    uint64_t moments = 0, integral = 0;
    const BallMoments m = ball.moments(x, size.minCoeff() / 20.0, &moments);
    ball.integral(x, size.minCoeff() / 20.0, &integral);
    EXPECT_GT(m.m0, 0.0);
    EXPECT_EQ(moments, 15u);
    EXPECT_EQ(moments, integral);
}

TEST(BallMomentsCount, WideCrossingBallCountsTwiceTheLatticeVisits) {
    // A moments visit (a cut cell's slab moments) costs about two lookups (ball_extinction.cpp).
    const auto media = repo_grid_medium("blob");
    const BallExtinction ball(media);
    const Bounds3 box = media[0]->bounds();
    const Vec3 size = box.hi - box.lo, x = box.lo + 0.3 * size;
    const double r = size.minCoeff() / 3.0;
    uint64_t counted = 0;
    const BallMoments m = ball.moments(x, r, &counted);
    const MassLattice lattice(*media[0], box);
    ASSERT_TRUE(lattice.wide_enough(r));
    double m0 = 0.0;
    Vec3 m1;
    Eigen::Matrix3d m2;
    uint64_t visits = 0;
    lattice.ball_moments(x, r, m0, m1, m2, &visits);
    EXPECT_EQ(m.m0, m0);   // the lattice's, so the visits are the ones counted
    EXPECT_GT(visits, 20u);
    EXPECT_EQ(counted, 2 * visits);
    // Two radii count both balls' work.
    uint64_t both = 0, other = 0;
    ball.moments(x, r, 0.8 * r, &both);
    ball.moments(x, 0.8 * r, &other);
    EXPECT_EQ(both, counted + other);
}

TEST(BallMomentsCount, ClippedBallCountsThePointsLookedUp) {
    // A wide ball crossing a box too elongated for the lattice (r under two of its longest cells)
    // takes the 4096 Halton points over its cube in the box; only those inside the ball are looked
    // up, and both integral() and moments() count exactly those.
    const std::vector<std::unique_ptr<Medium>> media = repo_grid_medium("plume");
    const BallExtinction ball(media);
    const Bounds3 box = media[0]->bounds();
    const Vec3 size = box.hi - box.lo;
    const MassLattice lattice(*media[0], box);
    // Between a quarter of the shortest side (the 15-point rule's reach) and two of the lattice's
    // longest cells (its reach): the plume's box is 0.64 x 1.52 x 0.77.
    const double r = 0.5 * (0.25 * size.minCoeff() + 2.0 * size.maxCoeff() / MassLattice::kCells);
    ASSERT_GT(4.0 * r, size.minCoeff());
    ASSERT_FALSE(lattice.wide_enough(r));
    const Vec3 x = box.lo + Vec3(0.1, 0.5, 0.5).cwiseProduct(size);
    uint64_t moments = 0, integral = 0;
    ball.moments(x, r, &moments);
    ball.integral(x, r, &integral);
    EXPECT_EQ(moments, integral);
    EXPECT_GT(moments, 500u);    // the ball holds about half of its clipped cube's points
    EXPECT_LT(moments, 4096u);   // but not the cube's corners, nor the part outside the box
}

TEST(BallMomentsCount, HomogeneousClosedFormCountsOne) {
    std::vector<std::unique_ptr<Medium>> media;
    media.push_back(std::make_unique<HomogeneousMedium>(HomogeneousMedium::box(Vec3::Zero(), Vec3::Constant(2.0), 1.0, Rgb::Constant(0.8), 0.0)));
    const BallExtinction ball(media);
    uint64_t counted = 0;
    const BallMoments m = ball.moments(Vec3::Constant(1.0), 0.5, &counted);
    EXPECT_NEAR(m.m0, 4.0 / 3.0 * kPi * 0.125, 1e-9);
    EXPECT_EQ(counted, 1u);
}
