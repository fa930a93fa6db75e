// GridMedium: delta and ratio tracking against analytic and quadrature references, locality of
// the majorant, the config factory. (Speed is measured in bench/bench_tracing.cpp, not here; the
// closed-form and extreme-density checks of the tracking are in tests/scene/media/majorant_tracking_test.cpp.)
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <thread>
#include <vector>

#include "core/error.h"
#include "scene/media/grid_medium.h"
#include "config/params.h"
#include "config/transform_params.h"
#include "io/vdb_io.h"

using namespace vpm;

namespace {

const std::string kMediaDir = VPM_SOURCE_DIR "/media";

struct MeanSe {
    double mean, se;
};
template <class F>
MeanSe estimate(int n, F&& sample) {
    double s = 0, s2 = 0;
    for (int i = 0; i < n; ++i) {
        const double x = sample(i);
        s += x;
        s2 += x * x;
    }
    const double mean = s / n;
    const double var = std::max(0.0, (s2 / n - mean * mean) * n / (n - 1.0));
    return {mean, std::sqrt(var / n)};
}

// A uniform density-1 grid of 40^3 voxels (index 0..39), world voxel size h.
DensityGrid uniform_grid(double h) {
    const Vec3i dims(40, 40, 40);
    DensityGrid g = DensityGrid::from_dense(Vec3i::Zero(), dims, std::vector<float>(size_t(dims.prod()), 1.0f));
    Eigen::Affine3d xf = Eigen::Affine3d::Identity();
    xf.scale(h);
    g.set_index_to_world(xf);
    return g;
}

// Optical depth by fine midpoint quadrature of sigma_t (the trilinear field is piecewise cubic).
double optical_depth(const Medium& m, const Ray& ray, double t1, int n = 200000) {
    const double dt = t1 / n;
    double tau = 0;
    for (int i = 0; i < n; ++i) tau += m.sigma_t(ray.at((i + 0.5) * dt));
    return tau * dt;
}

Ray make_ray(const Vec3& from, const Vec3& to, double& length) {
    Ray r;
    r.origin = from;
    r.dir = (to - from).normalized();
    length = (to - from).norm();
    return r;
}

}  // namespace

TEST(GridMedium, RatioTrackingUniformMatchesBeerLambert) {
    const double sigma = 1.5;
    const GridMedium m(uniform_grid(0.05), sigma, Rgb::Constant(0.8), 0.0);
    double L;
    // Both ends inside the constant region (index 0..39 -> world 0..1.95).
    const Ray ray = make_ray(Vec3(0.3, 0.4, 0.2), Vec3(0.66, 0.64, 1.3), L);
    Rng rng(1234);
    const auto r = estimate(40000, [&](int) { return m.transmittance(ray, L, rng); });
    const double expected = std::exp(-sigma * L);
    EXPECT_NEAR(r.mean, expected, 3 * r.se) << "se " << r.se;
    // Power check: 7% more extinction is clearly rejected with this sample size.
    EXPECT_GT(std::abs(r.mean - std::exp(-1.07 * sigma * L)), 3 * r.se);
}

TEST(GridMedium, RatioTrackingWithConfigTransform) {
    // Rotated, anisotropically scaled and translated: sigma_t is still 2.0 inside.
    Eigen::Affine3d cfg = Eigen::Affine3d::Identity();
    cfg.translate(Vec3(5, -2, 1));
    cfg.rotate(Eigen::AngleAxisd(0.7, Vec3(1, 1, 0).normalized()));
    cfg.scale(Vec3(2.0, 0.5, 1.0));
    const double sigma = 2.0;
    const GridMedium m(uniform_grid(0.05), sigma, Rgb::Constant(1.0), 0.3, cfg);
    const Eigen::Affine3d i2w = m.index_to_world();
    double L;
    const Ray ray = make_ray(i2w * Vec3(3, 10, 30), i2w * Vec3(35, 25, 4), L);
    EXPECT_NEAR(m.sigma_t(ray.at(0.5 * L)), sigma, 1e-12);
    Rng rng(99);
    const auto r = estimate(40000, [&](int) { return m.transmittance(ray, L, rng); });
    EXPECT_NEAR(r.mean, std::exp(-sigma * L), 3 * r.se) << "L " << L;
    // World bounds contain the transformed corners.
    EXPECT_TRUE(m.bounds().contains(i2w * Vec3(0, 0, 0)));
    EXPECT_TRUE(m.bounds().contains(i2w * Vec3(39, 39, 39)));
}

TEST(GridMedium, BoxVdbThroughWholeBox) {
    // box.vdb: density 1 on voxels 0..31 of size 1/32; along an axis through the whole box the
    // trilinear ramps at both faces add half a voxel each, so the optical depth is sigma * 1.
    const DensityGrid g = load_vdb_density(kMediaDir + "/box.vdb", "density");
    const double sigma = 1.2;
    const GridMedium m(g, sigma, Rgb::Constant(1.0), 0.0);
    Ray ray;
    ray.origin = Vec3(-3.0, 0.1, -0.2);
    ray.dir = Vec3(1, 0, 0);
    EXPECT_NEAR(optical_depth(m, ray, 6.0), sigma * 1.0, 1e-6);
    Rng rng(3);
    const auto r = estimate(400000, [&](int) { return m.transmittance(ray, kInfinity, rng); });
    EXPECT_NEAR(r.mean, std::exp(-sigma), 3 * r.se);
    EXPECT_GT(std::abs(r.mean - std::exp(-1.07 * sigma)), 3 * r.se);
}

TEST(GridMedium, DeltaTrackingFreeFlightDistribution) {
    const double sigma = 1.5;
    const GridMedium m(uniform_grid(0.05), sigma, Rgb::Constant(0.8), 0.0);
    double L;
    const Ray ray = make_ray(Vec3(0.3, 0.4, 0.2), Vec3(0.66, 0.64, 1.3), L);
    Rng rng(77);
    const int n = 40000;
    std::vector<double> t;
    t.reserve(n);
    int escaped = 0;
    for (int i = 0; i < n; ++i) {
        const double s = m.sample_free_flight(ray, L, rng);
        if (s == kInfinity) {
            ++escaped;
        } else {
            ASSERT_GT(s, 0.0);
            ASSERT_LT(s, L);
            t.push_back(s);
        }
    }
    std::sort(t.begin(), t.end());
    // Kolmogorov-Smirnov on [0, L] against F(x) = 1 - exp(-sigma x) (escapes sit above L).
    double D = 0;
    for (size_t i = 0; i < t.size(); ++i) {
        const double F = 1 - std::exp(-sigma * t[i]);
        D = std::max({D, std::abs(double(i + 1) / n - F), std::abs(double(i) / n - F)});
    }
    D = std::max(D, std::abs(double(t.size()) / n - (1 - std::exp(-sigma * L))));
    EXPECT_LT(D, 1.95 / std::sqrt(double(n)));   // alpha = 0.001
    const double p_esc = std::exp(-sigma * L);
    EXPECT_NEAR(double(escaped) / n, p_esc, 3 * std::sqrt(p_esc * (1 - p_esc) / n));
    // The test can fail: the same samples against sigma * 1.1 give a large D.
    double Dwrong = 0;
    for (size_t i = 0; i < t.size(); ++i)
        Dwrong = std::max(Dwrong, std::abs(double(i + 1) / n - (1 - std::exp(-1.1 * sigma * t[i]))));
    EXPECT_GT(Dwrong, 1.95 / std::sqrt(double(n)));
}

TEST(GridMedium, HeterogeneousPlumeAgreesWithQuadrature) {
    // Delta tracking's escape probability and ratio tracking's mean both estimate exp(-tau).
    const DensityGrid g = load_vdb_density(kMediaDir + "/plume.vdb", "density");
    const GridMedium m(g, 8.0, Rgb::Constant(0.9), 0.0);
    const Bounds3 b = m.bounds();
    const Vec3 c = 0.5 * (b.lo + b.hi);
    const Vec3 froms[3] = {Vec3(b.lo.x() - 0.5, 0.4, c.z()), Vec3(c.x() + 0.01, -0.3, c.z() - 0.02),
                           Vec3(c.x(), 0.9, c.z())};   // the last one starts inside, tmax infinite
    const Vec3 tos[3] = {Vec3(b.hi.x() + 0.5, 0.6, c.z() + 0.05), Vec3(c.x() - 0.03, 2.0, c.z() + 0.01),
                         Vec3(c.x() + 1, 1.2, c.z() - 1)};
    for (int k = 0; k < 3; ++k) {
        double L;
        const Ray ray = make_ray(froms[k], tos[k], L);
        const double tmax = (k == 2) ? kInfinity : L;
        const double tau = optical_depth(m, ray, (k == 2) ? 3.0 : L);
        const double T = std::exp(-tau);
        Rng rng(500 + k);
        const auto ratio = estimate(20000, [&](int) { return m.transmittance(ray, tmax, rng); });
        const auto delta = estimate(20000, [&](int) { return m.sample_free_flight(ray, tmax, rng) == kInfinity ? 1.0 : 0.0; });
        EXPECT_GT(tau, 0.3) << "ray " << k;   // the ray really crosses smoke
        EXPECT_NEAR(ratio.mean, T, 3.5 * ratio.se + 1e-6) << "ray " << k << ", tau " << tau;
        EXPECT_NEAR(delta.mean, T, 3.5 * delta.se + 1e-6) << "ray " << k << ", tau " << tau;
    }
}

TEST(GridMedium, GrazingAndAxisAlignedRays) {
    // Rays exactly on block faces, along axes, starting inside, on the boundary, pointing away.
    const double sigma = 0.8;
    const GridMedium m(uniform_grid(1.0), sigma, Rgb::Constant(1.0), 0.0);   // index == world
    struct Case {
        Vec3 o, d;
        double tmax;
    };
    const Case cases[] = {
        {Vec3(-5, 8, 16), Vec3(1, 0, 0), kInfinity},          // along block edge y=8, z=16
        {Vec3(8, 8, 8), Vec3(0, 0, 1), kInfinity},            // starts on a block corner, inside
        {Vec3(20, -1, 20), Vec3(0, 1, 0), 25.0},              // starts on the support boundary
        {Vec3(39.99, 39.99, 39.99), Vec3(-1, -1, -1), 10.0},  // starts in the upper ramp
        {Vec3(-1, 20, 20), Vec3(0, 0, 1), kInfinity},         // grazing the lower face (density 0)
        {Vec3(10, 10, 10), Vec3(-1, 0, 0), 3.0},
    };
    for (const auto& cs : cases) {
        Ray ray;
        ray.origin = cs.o;
        ray.dir = cs.d.normalized();
        const double tau = optical_depth(m, ray, std::isinf(cs.tmax) ? 120.0 : cs.tmax);
        Rng rng(1);
        const auto r = estimate(20000, [&](int) { return m.transmittance(ray, cs.tmax, rng); });
        EXPECT_NEAR(r.mean, std::exp(-tau), 3.5 * r.se + 1e-6) << cs.o.transpose() << " / " << cs.d.transpose();
        for (int i = 0; i < 1000; ++i) {
            const double s = m.sample_free_flight(ray, cs.tmax, rng);
            ASSERT_TRUE(s == kInfinity || (s > 0 && s < cs.tmax));
        }
    }
    // Missing the grid entirely, zero scale, zero tmax.
    Rng rng(2);
    Ray away;
    away.origin = Vec3(-5, -5, -5);
    away.dir = Vec3(-1, 0, 0);
    EXPECT_EQ(m.transmittance(away, kInfinity, rng), 1.0);
    EXPECT_EQ(m.sample_free_flight(away, kInfinity, rng), kInfinity);
    const GridMedium zero(uniform_grid(1.0), 0.0, Rgb::Constant(1.0), 0.0);
    Ray through;
    through.origin = Vec3(-5, 20, 20);
    through.dir = Vec3(1, 0, 0);
    EXPECT_EQ(zero.transmittance(through, kInfinity, rng), 1.0);
    EXPECT_EQ(m.sample_free_flight(through, 0.0, rng), kInfinity);
}

TEST(GridMedium, DenseVoxelInVacuumCostsLittleForMissingRays) {
    const Vec3i dims(64, 64, 64);
    std::vector<float> v(size_t(dims.prod()), 1e-4f);
    v[(size_t(40) * 64 + 40) * 64 + 40] = 1e6f;
    const GridMedium m(DensityGrid::from_dense(Vec3i::Zero(), dims, v), 1.0, Rgb::Constant(1.0), 0.0);
    Rng rng(8);
    TrackingStats stats;
    const int n = 2000;
    double sumT = 0;
    for (int i = 0; i < n; ++i) {
        Ray ray;   // random rays through the lower half, far from the voxel at (40, 40, 40)
        ray.origin = Vec3(-2, 2 + 20 * rng.uniform(), 2 + 20 * rng.uniform());
        ray.dir = Vec3(1, 0.2 * (rng.uniform() - 0.5), 0.2 * (rng.uniform() - 0.5)).normalized();
        sumT += m.transmittance(ray, kInfinity, rng, &stats);
        m.sample_free_flight(ray, kInfinity, rng, &stats);
    }
    // A global majorant (1e6 over ~65 voxels) would need ~6.5e7 lookups per ray.
    EXPECT_LT(double(stats.lookups) / (2 * n), 0.1);
    EXPECT_LT(double(stats.blocks) / (2 * n), 20.0);
    EXPECT_NEAR(sumT / n, std::exp(-1e-4 * 65), 0.01);
    // A ray through the voxel is opaque and terminates after a few evaluations: the voxel's cells
    // take the closed-form optical depth (majorant 1e6 over ~2 voxels would be ~2e6 null
    // collisions for delta tracking; it was ~1e7 with the 8^3-block majorants alone).
    Ray hit;
    hit.origin = Vec3(-2, 40, 40);
    hit.dir = Vec3(1, 0, 0);
    TrackingStats hs;
    const auto r = estimate(100, [&](int) { return m.transmittance(hit, kInfinity, rng, &hs); });
    EXPECT_EQ(r.mean, 0.0);
    EXPECT_LT(double(hs.lookups + hs.cells) / 100, 10.0) << "lookups " << hs.lookups << " cells " << hs.cells;
    TrackingStats fs;
    for (int i = 0; i < 100; ++i) EXPECT_LT(m.sample_free_flight(hit, kInfinity, rng, &fs), 44.0);   // collides at the voxel
    EXPECT_LT(double(fs.lookups + fs.cells) / 100, 10.0) << "lookups " << fs.lookups << " cells " << fs.cells;
}

TEST(GridMedium, ConcurrentTrackingIsDeterministic) {
    // The medium is shared const state: two threads get exactly the single-threaded results.
    const GridMedium m(load_vdb_density(kMediaDir + "/plume.vdb", "density"), 30.0, Rgb::Constant(1.0), 0.0);
    const Bounds3 b = m.bounds();
    auto run = [&](uint64_t stream, std::vector<double>& out) {
        Rng rng(2024, stream);
        for (int i = 0; i < 20000; ++i) {
            Ray ray;
            ray.origin = Vec3(b.lo.x() + rng.uniform() * (b.hi.x() - b.lo.x()), b.lo.y() + rng.uniform() * (b.hi.y() - b.lo.y()),
                              b.lo.z() + rng.uniform() * (b.hi.z() - b.lo.z()));
            ray.dir = Vec3(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5).normalized();
            out.push_back(m.transmittance(ray, kInfinity, rng));
            out.push_back(m.sample_free_flight(ray, kInfinity, rng));
        }
    };
    std::vector<double> a0, a1, b0, b1;
    run(0, a0);
    run(1, a1);
    std::thread t0([&] { run(0, b0); }), t1([&] { run(1, b1); });
    t0.join();
    t1.join();
    EXPECT_EQ(a0, b0);
    EXPECT_EQ(a1, b1);
}

TEST(GridMedium, FactoryReadsKeysAndReportsErrors) {
    const auto make = [](const std::string& toml) {
        auto doc = parse_config(toml, "test.toml", kMediaDir);
        toml::table resolved;
        Params root(doc, &resolved);
        auto media = root.tables("media");
        return make_grid_medium(media.at(0));
    };
    auto m = make(R"(
[[media]]
type = "grid"
file = "box.vdb"
sigma_t_scale = 2.5
albedo = [0.9, 0.8, 0.7]
g = 0.4
transform = { scale = 2, rotate = [0, 1, 0, 90], translate = [0, 1, 0] }
)");
    const auto* gm = dynamic_cast<const GridMedium*>(m.get());
    ASSERT_NE(gm, nullptr);
    EXPECT_EQ(gm->grid().name(), "density");
    EXPECT_DOUBLE_EQ(gm->g(), 0.4);
    EXPECT_DOUBLE_EQ(gm->albedo()[2], 0.7);
    // box.vdb is the unit cube around the origin; scaled by 2 and lifted by 1.
    EXPECT_NEAR(gm->sigma_t(Vec3(0.9, 1.9, -0.9)), 2.5, 1e-9);
    EXPECT_EQ(gm->sigma_t(Vec3(0, 2.1, 0)), 0.0);
    EXPECT_NE(m->describe().find("box.vdb"), std::string::npos);

    const auto expect_config_error = [&](const std::string& toml, const std::string& part) {
        try {
            make(toml);
            ADD_FAILURE() << "no error for: " << toml;
        } catch (const ConfigError& e) {
            EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
        }
    };
    expect_config_error("[[media]]\nfile = \"box.vdb\"\ngrid = \"smoke\"\n", "'density' (float)");
    expect_config_error("[[media]]\nfile = \"missing.vdb\"\n", "missing.vdb");
    expect_config_error("[[media]]\nfile = \"box.vdb\"\ng = 1.0\n", "media.0.g");
    expect_config_error("[[media]]\nfile = \"box.vdb\"\nsigma_t_scale = -1\n", "sigma_t_scale");
    expect_config_error("[[media]]\nfile = \"box.vdb\"\nalbedo = 1.5\n", "albedo");
    expect_config_error("[[media]]\nfile = \"box.vdb\"\ntransform = { scale = 0 }\n", "scale");
    expect_config_error("[[media]]\nfile = \"box.vdb\"\ntransform = { rotate = [0, 0, 0, 10] }\n", "rotate");
    expect_config_error("[[media]]\nfile = \"box.vdb\"\ntransform = { sclae = 2 }\n", "sclae");
}

TEST(TransformParams, ScaleThenRotateThenTranslate) {
    auto doc = parse_config("[t]\nscale = [1, 2, 3]\nrotate = [0, 0, 2, 90]\ntranslate = [10, 0, 0]\n", "t.toml", ".");
    toml::table resolved;
    Params root(doc, &resolved);
    Params t = root.table("t");
    const Eigen::Affine3d m = read_transform(t);
    // (1,1,1) -> scale (1,2,3) -> rotate 90 deg about z (-2,1,3) -> translate (8,1,3).
    EXPECT_TRUE((m * Vec3(1, 1, 1)).isApprox(Vec3(8, 1, 3), 1e-12)) << (m * Vec3(1, 1, 1)).transpose();
    Params none = root.table("absent");
    EXPECT_TRUE(read_transform(none).matrix().isIdentity());
}
