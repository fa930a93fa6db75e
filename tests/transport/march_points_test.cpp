// place_march_points: the points follow the exact free-flight density of the medium, stratified.
// Point j's optical depth tau_j (by midpoint quadrature) must put 1 - exp(-tau_j) in stratum j of
// the mass P, and the position within the stratum must be uniform (Kolmogorov-Smirnov over many
// draws); a density that followed a majorant instead would fail both.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "io/vdb_io.h"
#include "scene/media/grid_medium.h"
#include "transport/march_points.h"

using namespace vpm;

namespace {

// Cumulative optical depth on a fine grid of the segment, for looking up many points.
struct DepthTable {
    std::vector<double> cum;
    double dt;
    DepthTable(const Medium& m, const Ray& ray, double t1, int n) : cum(size_t(n) + 1, 0.0), dt(t1 / n) {
        for (int i = 0; i < n; ++i) cum[size_t(i) + 1] = cum[size_t(i)] + m.sigma_t(ray.at((i + 0.5) * dt)) * dt;
    }
    double at(double t) const {   // linear between nodes: the error is O(dt^2 sigma')
        const double x = t / dt;
        const size_t i = std::min(size_t(x), cum.size() - 2);
        return cum[i] + (x - double(i)) * (cum[i + 1] - cum[i]);
    }
};

}  // namespace

TEST(MarchPoints, StratifiedFreeFlightDensityInAGrid) {
    // The blob at a peak sigma_t that makes its block majorants loose (issue 20: weights up to 869).
    const GridMedium m(load_vdb_density(VPM_SOURCE_DIR "/media/blob.vdb", ""), 8.0, Rgb::Constant(0.9), 0.0);
    const Bounds3 b = m.bounds();
    const Vec3 from(b.lo.x() - 0.3, 0.1 * b.hi.y(), 0.2 * b.hi.z()), to(b.hi.x() + 0.3, -0.1 * b.hi.y(), 0.1 * b.hi.z());
    const double L = (to - from).norm();
    const Ray ray{from, (to - from) / L};
    const DepthTable table(m, ray, L, 400000);
    const double tau = table.cum.back();
    ASSERT_GT(tau, 1.0);
    ASSERT_LT(tau, 30.0);
    const int n = 4, draws = 4000;
    OpticalDepthProfile profile;
    std::vector<double> ts, within;
    Rng rng(77);
    double mass = 0.0;
    for (int d = 0; d < draws; ++d) {
        mass = place_march_points(m, ray, L, n, rng, profile, ts);
        ASSERT_EQ(ts.size(), size_t(n));
        for (int j = 0; j < n; ++j) {
            const double x = -std::expm1(-table.at(ts[size_t(j)])) / mass * n - j;   // in [0, 1) for stratum j
            ASSERT_GT(x, -1e-6) << "point " << j;
            ASSERT_LT(x, 1.0 + 1e-6) << "point " << j;
            within.push_back(x);
        }
    }
    EXPECT_NEAR(mass, -std::expm1(-tau), 1e-6);
    std::sort(within.begin(), within.end());
    double D = 0.0;
    const double N = double(within.size());
    for (size_t i = 0; i < within.size(); ++i)
        D = std::max({D, std::abs((i + 1) / N - within[i]), std::abs(i / N - within[i])});
    EXPECT_LT(D, 1.95 / std::sqrt(N));   // KS at 0.1%
}

TEST(MarchPoints, NoPointsOffTheMedium) {
    const GridMedium m(load_vdb_density(VPM_SOURCE_DIR "/media/blob.vdb", ""), 8.0, Rgb::Constant(0.9), 0.0);
    const Bounds3 b = m.bounds();
    OpticalDepthProfile profile;
    std::vector<double> ts{1.0};
    Rng rng(1);
    const Ray miss{Vec3(b.hi.x() + 1.0, 0, 0), Vec3(0, 1, 0)};
    EXPECT_EQ(place_march_points(m, miss, 10.0, 4, rng, profile, ts), 0.0);
    EXPECT_TRUE(ts.empty());
}
