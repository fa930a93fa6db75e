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
#include "scene/media/homogeneous_medium.h"
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

// photons.march_points (transport/march_count.h): each count rule must estimate the segment's
// single-scattering integral without bias. In a homogeneous slab of optical depth tau along the
// ray, sum_j f(t_j) mass / divisor estimates I = integral_0^L sigma e^(-sigma t) f(t) dt, here
// with f(t) = 1 + t (closed form). The tolerance is 4 standard errors of the mean over the draws;
// a rule that kept free_flight's weight 1 / n but stratified over the segment's mass only would
// read P times too low, one that kept P / n with ceil(n P) points up to n / ceil(n P) too high.
namespace {

struct RuleMoments {
    double mean = 0.0, se = 0.0, mean_count = 0.0;
    int min_count = 1 << 30, max_count = 0;
};

RuleMoments draw(const Medium& m, const Ray& ray, double L, int n, MarchCount count, int draws, uint64_t seed) {
    OpticalDepthProfile profile;
    std::vector<double> ts;
    Rng rng(seed);
    double s = 0.0, s2 = 0.0, c = 0.0;
    RuleMoments r;
    for (int d = 0; d < draws; ++d) {
        const MarchMass w = place_counted_march_points(m, ray, L, n, count, rng, profile, ts);
        double e = 0.0;
        for (const double t : ts) e += (1.0 + t) * w.mass / w.divisor;
        s += e;
        s2 += e * e;
        c += double(ts.size());
        r.min_count = std::min(r.min_count, int(ts.size()));
        r.max_count = std::max(r.max_count, int(ts.size()));
    }
    r.mean = s / draws;
    r.se = std::sqrt(std::max(0.0, s2 / draws - r.mean * r.mean) / (draws - 1));
    r.mean_count = c / draws;
    return r;
}

}  // namespace

TEST(MarchPoints, EveryCountRuleIsUnbiased) {
    const double sigma = 0.25;   // the slab [0, 2] along x: tau 0.5, P = 0.39, 4 P = 1.57
    const auto m = HomogeneousMedium::box(Vec3(0, -1, -1), Vec3(2, 1, 1), sigma, Rgb::Constant(0.9), 0.0);
    const Ray ray{Vec3(0, 0, 0), Vec3(1, 0, 0)};
    const double L = 2.0, P = -std::expm1(-sigma * L);
    // integral_0^L sigma e^(-sigma t) (1 + t) dt = P + (1 - e^(-sigma L) (1 + sigma L)) / sigma
    const double exact = P + (1.0 - std::exp(-sigma * L) * (1.0 + sigma * L)) / sigma;
    const int n = 4, draws = 40000;
    for (const MarchCount rule : {MarchCount::fixed, MarchCount::mass, MarchCount::free_flight}) {
        const RuleMoments r = draw(m, ray, L, n, rule, draws, 5);
        EXPECT_NEAR(r.mean, exact, 4.0 * r.se + 1e-12) << "rule " << int(rule);
        if (rule == MarchCount::fixed) {
            EXPECT_EQ(r.min_count, n);
            EXPECT_EQ(r.max_count, n);
        } else if (rule == MarchCount::mass) {
            EXPECT_EQ(r.min_count, 2);   // ceil(4 P)
            EXPECT_EQ(r.max_count, 2);
        } else {
            // Stratum 0 always inside, stratum 1 (which straddles 4 P = 1.57) with probability 0.57.
            EXPECT_EQ(r.min_count, 1);
            EXPECT_EQ(r.max_count, 2);
            const double count_se = 0.5 / std::sqrt(double(draws));
            EXPECT_NEAR(r.mean_count, n * P, 4.0 * count_se);
        }
    }
    // A thick segment (P ~ 1) gets n points under every rule, a thin one (4 P < 1) one point under
    // "mass" and at most one under "free_flight".
    const auto thin = HomogeneousMedium::box(Vec3(0, -1, -1), Vec3(2, 1, 1), 0.05, Rgb::Constant(0.9), 0.0);
    EXPECT_EQ(draw(thin, ray, L, n, MarchCount::mass, 100, 6).max_count, 1);
    EXPECT_EQ(draw(thin, ray, L, n, MarchCount::free_flight, 100, 6).max_count, 1);
    const auto thick = HomogeneousMedium::box(Vec3(0, -1, -1), Vec3(2, 1, 1), 40.0, Rgb::Constant(0.9), 0.0);
    for (const MarchCount rule : {MarchCount::mass, MarchCount::free_flight})
        EXPECT_EQ(draw(thick, ray, L, n, rule, 100, 7).min_count, n);
}

TEST(MarchPoints, FixedCountKeepsThePointsOfTheMarch) {
    // "fixed" is the march before the count rules: the same points from the same random numbers.
    const GridMedium m(load_vdb_density(VPM_SOURCE_DIR "/media/blob.vdb", ""), 8.0, Rgb::Constant(0.9), 0.0);
    const Bounds3 b = m.bounds();
    const Ray ray{Vec3(b.lo.x() - 0.3, 0.0, 0.0), Vec3(1, 0, 0)};
    OpticalDepthProfile profile;
    std::vector<double> a, c;
    Rng ra(3), rc(3);
    for (int d = 0; d < 50; ++d) {
        const double P = place_march_points(m, ray, 100.0, 4, ra, profile, a);
        const MarchMass w = place_counted_march_points(m, ray, 100.0, 4, MarchCount::fixed, rc, profile, c);
        ASSERT_GT(P, 0.0);
        EXPECT_EQ(w.mass, P);
        EXPECT_EQ(w.divisor, 4);
        EXPECT_EQ(a, c);
    }
}

TEST(MarchScratch, NestedCallsTakeTheirOwnSlotAndReturnIt) {
    // for_each_march_point's scratch is the thread's: a visit that marches again (nested) must not
    // get the profile its caller is still inverting, and a finished call's slot is reused.
    const OpticalDepthProfile* outer = nullptr;
    const OpticalDepthProfile* inner = nullptr;
    {
        MarchScratch a;
        outer = &a.profile;
        {
            MarchScratch b;
            inner = &b.profile;
            EXPECT_NE(inner, outer);
            EXPECT_NE(&b.ts, &a.ts);
        }
        MarchScratch c;   // the nested slot again
        EXPECT_EQ(&c.profile, inner);
    }
    MarchScratch d;
    EXPECT_EQ(&d.profile, outer);
}
