// The walk-neighbour estimate (photon/estimate/walk_estimate.h): exact for clustered photons of
// independent walks where the photon-neighbour corrected form is biased; the map front ends;
// the rules; bad keys.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "core/error.h"
#include "core/henyey_greenstein.h"
#include "core/sampling/rng.h"
#include "core/sampling/sampling.h"
#include "photon/estimate/walk_estimate.h"

using namespace vpm;

namespace {

struct Near {
    double d2;
    uint32_t walk;
    bool operator<(const Near& o) const { return d2 < o.d2 || (d2 == o.d2 && walk < o.walk); }
};

// N walks in the periodic unit cube, each a uniform parent and 1 + Poisson(2) photons within a
// Gaussian of sigma 0.02 around it (strong clustering at the balls of k = 8); distances from the
// cube's centre with periodic images. Density: N * 3 photons per unit volume.
std::vector<Near> clustered_trial(size_t walks, Rng& rng) {
    std::vector<Near> out;
    const Vec3 q(0.5, 0.5, 0.5);
    for (size_t w = 0; w < walks; ++w) {
        const Vec3 parent(rng.uniform(), rng.uniform(), rng.uniform());
        // 1 + Poisson(2) by inversion
        int extra = 0;
        double p = std::exp(-2.0), c = p, u = rng.uniform();
        while (u > c) {
            ++extra;
            p *= 2.0 / extra;
            c += p;
        }
        for (int j = 0; j <= extra; ++j) {
            double d2 = 0.0;
            for (int a = 0; a < 3; ++a) {
                const double u1 = std::max(rng.uniform(), 1e-300), u2 = rng.uniform();
                const double g = std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * kPi * u2);
                double x = parent[a] + 0.02 * g;
                x -= std::floor(x);
                double d = std::abs(x - q[a]);
                d = std::min(d, 1.0 - d);
                d2 += d * d;
            }
            out.push_back(Near{d2, uint32_t(w)});
        }
    }
    std::sort(out.begin(), out.end());
    return out;
}

struct Moments {
    double sum = 0, sum2 = 0;
    size_t n = 0;
    void add(double v) {
        sum += v;
        sum2 += v * v;
        ++n;
    }
    double mean() const { return sum / double(n); }
    double se() const { return std::sqrt((sum2 / double(n) - mean() * mean()) / double(n - 1)); }
};

}  // namespace

// For N i.i.d. walks the walk corrected estimate is unbiased however a walk's photons cluster
// (F(R) ~ Beta(k, N - k + 1), E[1/F] = N / (k - 1)); the photon corrected one reads high there.
// 6000 independent trials, tolerance 4 standard errors.
TEST(WalkEstimate, WalkCorrectedIsUnbiasedForClusteredWalks) {
    const size_t walks = 400, k = 8, trials = 6000;
    const double density = double(walks) * 3.0;   // E[photons per walk] = 3
    const Estimator corrected = Estimator::named("corrected"), classic = Estimator::named("classic");
    Moments walk_corrected, walk_classic, photon_corrected;
    std::vector<double> w, d2;
    std::vector<uint32_t> slots;
    for (size_t t = 0; t < trials; ++t) {
        Rng rng(2026, t);
        const std::vector<Near> all = clustered_trial(walks, rng);
        w.assign(all.size(), 1.0 / density);
        d2.resize(all.size());
        for (size_t i = 0; i < all.size(); ++i) d2[i] = all[i].d2;
        auto walk_of = [&](size_t i) { return all[i].walk; };
        const Estimate<double> wc = estimate_density_walks<double>(corrected, w.data(), d2.data(), all.size(), walk_of,
                                                                   true, k, kInfinity, 3, slots);
        ASSERT_EQ(wc.kind, EstimateCase::knn);
        ASSERT_LT(wc.radius, 0.5);   // a true ball of the periodic cube
        walk_corrected.add(wc.value);
        walk_classic.add(estimate_density_walks<double>(classic, w.data(), d2.data(), all.size(), walk_of, true, k,
                                                        kInfinity, 3, slots)
                             .value);
        photon_corrected.add(estimate_density<double>(corrected, w.data(), d2.data(), all.size(), true, k, kInfinity, 3).value);
    }
    EXPECT_NEAR(walk_corrected.mean(), 1.0, 4.0 * walk_corrected.se())
        << "walk corrected " << walk_corrected.mean() << " +- " << walk_corrected.se();
    EXPECT_GT(photon_corrected.mean() - 1.0, 4.0 * photon_corrected.se())
        << "photon corrected " << photon_corrected.mean() << " +- " << photon_corrected.se();
    // Classic adds the k-th walk's photon at R: at most 1/(k-1) above corrected, more than nothing.
    EXPECT_GT(walk_classic.mean(), walk_corrected.mean());
    EXPECT_LT(walk_classic.mean() - walk_corrected.mean(), 1.0 / double(k - 1));
}

// Walk neighbourhood on a list where every photon has its own walk: the photon estimate exactly.
TEST(WalkEstimate, DistinctWalksGiveThePhotonEstimate) {
    std::vector<double> w(50), d2(50);
    for (size_t i = 0; i < 50; ++i) {
        w[i] = 1.0 + 0.01 * double(i);
        d2[i] = 0.001 * double(i + 1) * double(i + 1);
    }
    std::vector<uint32_t> slots;
    auto own = [](size_t i) { return uint32_t(i); };
    for (const char* name : {"classic", "corrected"})
        for (size_t k : {2u, 5u, 32u}) {
            const Estimator e = Estimator::named(name);
            const double a = estimate_density_walks<double>(e, w.data(), d2.data(), 50, own, false, k, kInfinity, 3, slots).value;
            const double b = estimate_density<double>(e, w.data(), d2.data(), 50, false, k, kInfinity, 3).value;
            EXPECT_EQ(a, b) << name << " k " << k;
        }
    // Two photons per walk: corrected sums the 2(k-1) photons of the k-1 nearer walks.
    auto pairs = [](size_t i) { return uint32_t(i / 2); };
    const double v = estimate_density_walks<double>(Estimator::named("corrected"), w.data(), d2.data(), 50, pairs, false,
                                                    4, kInfinity, 3, slots)
                         .value;
    double sum = 0;
    for (size_t i = 0; i < 6; ++i) sum += w[i];
    EXPECT_DOUBLE_EQ(v, sum / ball_volume(3, std::sqrt(d2[6])));
}

TEST(WalkEstimate, FewerWalksThanKWithinTheRadiusIsTheFixedRadiusEstimate) {
    std::vector<double> w = {1, 1, 1, 1}, d2 = {0.01, 0.02, 0.03, 0.04};
    std::vector<uint32_t> slots;
    auto walk_of = [](size_t i) { return uint32_t(i / 2); };   // 2 walks
    const Estimate<double> e = estimate_density_walks<double>(Estimator::named("corrected"), w.data(), d2.data(), 4, walk_of,
                                                              true, 8, 0.5, 3, slots);
    EXPECT_EQ(e.kind, EstimateCase::fixed_radius);
    EXPECT_DOUBLE_EQ(e.value, 4.0 / ball_volume(3, 0.5));
}

TEST(WalkEstimate, BadNeighbourhoodAndEstimatorAreOneClearError) {
    EXPECT_EQ(parse_neighbourhood("walks"), Neighbourhood::walks);
    EXPECT_EQ(parse_neighbourhood("photons"), Neighbourhood::photons);
    try {
        parse_neighbourhood("walk");
        FAIL() << "no error";
    } catch (const Error& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("photons.neighbours"), std::string::npos) << m;
        EXPECT_NE(m.find("\"walk\""), std::string::npos) << m;
        EXPECT_NE(m.find("\"photons\", \"walks\""), std::string::npos) << m;
    }
    try {
        validate_walk_estimator(Estimator::named("mse_optimal"));
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("allowed: \"classic\", \"corrected\""), std::string::npos) << e.what();
    }
}

// The map front ends gather knn_walks and weigh as estimate_in_scattering / estimate_surface_irradiance.
TEST(WalkEstimate, MapFrontEndsMatchTheListEstimate) {
    Rng rng(3, 0);
    std::vector<PhotonInput> in;
    for (uint64_t w = 0; w < 2000; ++w) {
        Vec3 x(rng.uniform(), rng.uniform(), rng.uniform());
        for (int j = 0; j < 3; ++j) {
            PhotonInput p;
            p.position = x;
            p.direction = sample_uniform_sphere(rng.uniform(), rng.uniform());
            p.power = Rgb(1.0, 2.0, 3.0) * (1.0 + rng.uniform());
            p.walk = w;
            in.push_back(p);
            x += 0.03 * sample_uniform_sphere(rng.uniform(), rng.uniform());
        }
    }
    const PhotonMap map(in);
    GatherBuffers buf;
    NeighbourList list;
    std::vector<uint32_t> slots;
    const Vec3 wo = Vec3(1, 2, 3).normalized(), n = Vec3::UnitZ();
    for (int q = 0; q < 20; ++q) {
        const Vec3 x(0.2 + 0.6 * rng.uniform(), 0.2 + 0.6 * rng.uniform(), 0.2 + 0.6 * rng.uniform());
        for (const char* name : {"classic", "corrected"}) {
            const Estimator e = Estimator::named(name);
            const Estimate<Rgb> a = estimate_in_scattering_walks(map, x, wo, 0.6, e, 16, kInfinity, buf);
            const Estimate<Rgb> s = estimate_surface_irradiance_walks(map, x, n, e, 16, kInfinity, buf);
            size_t walks = 0;
            const size_t found = map.knn_walks(x, 16, kInfinity, list, walks);
            ASSERT_EQ(walks, 16u);
            std::vector<Rgb> wv(found), ws(found);
            std::vector<double> d2(found);
            for (size_t i = 0; i < found; ++i) {
                wv[i] = hg_eval(list[i].direction.dot(wo), 0.6) * list[i].power;
                ws[i] = list[i].direction.dot(n) < 0.0 ? list[i].power : Rgb::Zero();
                d2[i] = list[i].d2;
            }
            auto walk_of = [&](size_t i) { return list[i].walk; };
            const Estimate<Rgb> ra = estimate_density_walks<Rgb>(e, wv.data(), d2.data(), found, walk_of, false, 16, kInfinity, 3, slots);
            const Estimate<Rgb> rs = estimate_density_walks<Rgb>(e, ws.data(), d2.data(), found, walk_of, false, 16, kInfinity, 2, slots);
            EXPECT_TRUE((a.value == ra.value).all()) << name;
            EXPECT_TRUE((s.value == rs.value).all()) << name;
            EXPECT_EQ(a.k_used, found);
        }
    }
}
