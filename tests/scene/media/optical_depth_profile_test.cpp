// OpticalDepthProfile from both media: its total and its inverse against midpoint quadrature of
// sigma_t (the trilinear field is piecewise cubic along a ray, so the quadrature is accurate to
// ~1e-9 relative here), and the cut at kEnoughDepth in a dense grid.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/sampling/rng.h"
#include "io/vdb_io.h"
#include "scene/media/grid_medium.h"
#include "scene/media/homogeneous_medium.h"
#include "scene/media/tracking_counter.h"

using namespace vpm;

namespace {

double quadrature_depth(const Medium& m, const Ray& ray, double t1, int n = 200000) {
    const double dt = t1 / n;
    double tau = 0;
    for (int i = 0; i < n; ++i) tau += m.sigma_t(ray.at((i + 0.5) * dt));
    return tau * dt;
}

Ray ray_through(const Vec3& from, const Vec3& to, double& length) {
    length = (to - from).norm();
    return Ray{from, (to - from) / length};
}

GridMedium plume() {
    return GridMedium(load_vdb_density(VPM_SOURCE_DIR "/media/plume.vdb", "density"), 8.0, Rgb::Constant(0.9), 0.0);
}

// A chord across the plume, through smoke and out again.
Ray plume_chord(const GridMedium& m, double& length) {
    const Bounds3 b = m.bounds();
    const Vec3 c = 0.5 * (b.lo + b.hi);
    return ray_through(Vec3(b.lo.x() - 0.5, 0.4, c.z() - 0.1), Vec3(b.hi.x() + 0.5, 0.6, c.z() + 0.05), length);
}

}  // namespace

TEST(OpticalDepthProfile, PlumeTotalAndInverseMatchQuadrature) {
    const GridMedium m = plume();
    double L;
    const Ray ray = plume_chord(m, L);
    OpticalDepthProfile p;
    m.optical_depth_profile(ray, L, p);
    const double tau = quadrature_depth(m, ray, L);
    ASSERT_GT(tau, 0.3);   // the ray crosses smoke
    ASSERT_LT(tau, OpticalDepthProfile::kEnoughDepth);
    EXPECT_GT(p.size(), 20u);   // voxel cells, not one majorant piece
    EXPECT_NEAR(p.total(), tau, 1e-6 * tau);
    for (double f : {0.01, 0.2, 0.5, 0.8, 0.99}) {
        size_t cursor = 0;
        const double t = p.invert(f * p.total(), cursor);
        ASSERT_GT(t, 0.0);
        ASSERT_LT(t, L);
        EXPECT_NEAR(quadrature_depth(m, ray, t), f * p.total(), 1e-6 * tau) << "fraction " << f;
    }
}

TEST(OpticalDepthProfile, TheWalkIsCountedForThePlansWork) {
    // The auto plan prices the march by these counts (render/plan/work_units.h): the profile's blocks as
    // steps and its voxel cells as closed-form cells, on this thread. Uncounted, the march cost about
    // 2x what the plan charged in grids (docs/studies/auto_plan.md section 28).
    const GridMedium m = plume();
    double L;
    const Ray ray = plume_chord(m, L);
    const TrackingCounts before = thread_tracking_counts();
    OpticalDepthProfile p;
    m.optical_depth_profile(ray, L, p);
    const TrackingCounts after = thread_tracking_counts();
    EXPECT_GE(after.steps - before.steps, 1u);
    EXPECT_GT(after.cells - before.cells, 20u);           // the voxel cells crossed, as the pieces
    EXPECT_LE(after.cells - before.cells, uint64_t(p.size()));
    EXPECT_EQ(after.lookups, before.lookups);              // closed forms, no point lookups
}

TEST(OpticalDepthProfile, GridPiecesAreTheVoxelCellsCrossed) {
    // The profile walks each 8^3 block's voxel cells in one DDA (GridMedium::optical_depth_profile):
    // its total and inverse against midpoint quadrature on random chords of the blob, with the
    // identity transform and a rotated, scaled one (the walk's faces and stencils off the axes).
    for (const bool rotated : {false, true}) {
        Eigen::Affine3d xf = Eigen::Affine3d::Identity();
        if (rotated) xf.rotate(Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized())).scale(1.3);
        const GridMedium m(load_vdb_density(VPM_SOURCE_DIR "/media/blob.vdb"), 3.0, Rgb::Constant(0.9), 0.0, xf);
        const Bounds3 b = m.bounds();
        Rng rng(22, rotated);
        for (int r = 0; r < 20; ++r) {
            // Chords through the middle half of the box, where the blob's density lies.
            const Vec3 c = 0.5 * (b.lo + b.hi), h = 0.25 * (b.hi - b.lo);
            const Vec3 from(b.lo.x() - 1.0, c.y() + (2 * rng.uniform() - 1) * h.y(), c.z() + (2 * rng.uniform() - 1) * h.z());
            const Vec3 to(b.hi.x() + 1.0, c.y() + (2 * rng.uniform() - 1) * h.y(), c.z() + (2 * rng.uniform() - 1) * h.z());
            double L;
            const Ray ray = ray_through(from, to, L);
            OpticalDepthProfile p;
            m.optical_depth_profile(ray, L, p);
            const double tau = quadrature_depth(m, ray, L, 100000);
            ASSERT_GT(tau, 0.05);
            ASSERT_FALSE(p.empty());
            EXPECT_NEAR(p.total(), tau, 1e-6 * tau + 1e-12);
            // The inverse is monotone and lands where quadrature reaches each depth.
            double t_prev = 0.0;
            size_t cursor = 0;
            for (double f : {0.1, 0.3, 0.5, 0.7, 0.9}) {
                const double t = p.invert(f * p.total(), cursor);
                EXPECT_GE(t, t_prev);
                t_prev = t;
                EXPECT_NEAR(quadrature_depth(m, ray, t, 100000), f * p.total(), 1e-6 * tau + 1e-12);
            }
        }
    }
}

TEST(OpticalDepthProfile, DenseGridStopsOnceTheDepthIsEnough) {
    // sigma_t_scale 1e4 over the plume: the chord's depth is ~1e4, the profile stops past 40.
    const GridMedium m(load_vdb_density(VPM_SOURCE_DIR "/media/plume.vdb", "density"), 1e4, Rgb::Constant(0.9), 0.0);
    const Bounds3 b = m.bounds();
    const Vec3 c = 0.5 * (b.lo + b.hi);
    double L;
    const Ray ray = ray_through(Vec3(b.lo.x() - 0.5, 0.4, c.z()), Vec3(b.hi.x() + 0.5, 0.6, c.z()), L);
    OpticalDepthProfile whole, cut;
    const GridMedium thin(load_vdb_density(VPM_SOURCE_DIR "/media/plume.vdb", "density"), 1e-3, Rgb::Constant(0.9), 0.0);
    thin.optical_depth_profile(ray, L, whole);   // far below the cut: every cell of the chord
    m.optical_depth_profile(ray, L, cut);
    EXPECT_GE(cut.total(), OpticalDepthProfile::kEnoughDepth);
    EXPECT_LT(cut.size(), whole.size() / 2);
    // Up to the cut both agree on where a depth is reached.
    size_t c1 = 0, c2 = 0;
    const double t_cut = cut.invert(30.0, c1), t_whole = whole.invert(30.0 * 1e-3 / 1e4, c2);
    EXPECT_NEAR(t_cut, t_whole, 1e-9 * L);
}

TEST(OpticalDepthProfile, HomogeneousSphereIsOneExactPiece) {
    const HomogeneousMedium m = HomogeneousMedium::sphere(Vec3(0, 0, 0), 1.0, 3.0, Rgb::Constant(0.9), 0.0);
    const Ray ray{Vec3(0, 0.6, -5), Vec3(0, 0, 1)};   // chord 1.6 from t = 4.2 to 5.8
    OpticalDepthProfile p;
    m.optical_depth_profile(ray, 10.0, p);
    ASSERT_EQ(p.size(), 1u);
    EXPECT_NEAR(p.total(), 3.0 * 1.6, 1e-12);
    size_t cursor = 0;
    EXPECT_NEAR(p.invert(1.5, cursor), 4.2 + 0.5, 1e-12);
    m.optical_depth_profile(ray, 4.0, p);   // ends before the sphere
    EXPECT_TRUE(p.empty());
    EXPECT_EQ(p.total(), 0.0);
}
