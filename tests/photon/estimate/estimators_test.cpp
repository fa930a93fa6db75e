// The estimators: exact formulas, the rules (a)(b)(c), and Monte Carlo against order statistics.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/henyey_greenstein.h"
#include "core/sampling/rng.h"
#include "core/sampling/sampling.h"
#include "photon/estimate/estimators.h"
#include "photon/map/photon_map.h"

using namespace vpm;

TEST(Estimators, NamesParseValidateWarn) {
    for (const Estimator& e : Estimator::all()) EXPECT_EQ(Estimator::named(e.name()), e);
    EXPECT_THROW(Estimator::named("k-1"), Error);
    // classic at k = 1: infinite mean, or identically 0 with a kernel vanishing at the rim (issue 24)
    EXPECT_THROW(Estimator::named("classic").validate_k(1), Error);
    EXPECT_NO_THROW(Estimator::named("classic").validate_k(2));
    EXPECT_THROW(Estimator::named("classic").validate_k(0), Error);
    EXPECT_THROW(Estimator::named("corrected").validate_k(1), Error);
    EXPECT_NO_THROW(Estimator::named("corrected").validate_k(2));
    EXPECT_THROW(Estimator::named("mse_optimal").validate_k(2), Error);
    EXPECT_NO_THROW(Estimator::named("mse_optimal").validate_k(3));
    EXPECT_FALSE(Estimator::named("corrected").warning(2).empty());
    EXPECT_TRUE(Estimator::named("corrected").warning(3).empty());
    EXPECT_TRUE(Estimator::named("classic").warning(2).empty());
    EXPECT_DOUBLE_EQ(ball_volume(2, 2.0), kPi * 4.0);
    EXPECT_DOUBLE_EQ(ball_volume(3, 2.0), 4.0 / 3.0 * kPi * 8.0);
    EXPECT_THROW(ball_volume(4, 1.0), Error);
}

// The traits agree with the formulas: the classic sum keeps the k-th neighbour, and a unit-weight
// estimate counts k photons exactly when it does (unit_weight_count); the forms the renderer
// combines with photon beams and leave-group-out are the unshrunk sums.
TEST(Estimators, TraitsAgreeWithTheFormulas) {
    for (const Estimator& e : Estimator::all()) {
        const double k = 8.0;
        EXPECT_EQ(e.traits().keeps_kth, e.entry().unit_weight_count(8) == k) << e.name();
        const bool unshrunk = e.entry().unit_weight_count(8) >= k - 1.0;
        if (e.traits().photon_beams || e.traits().leave_group_out) {
            EXPECT_TRUE(unshrunk) << e.name();
        }
        if (e.traits().leave_group_out) {
            EXPECT_FALSE(e.traits().keeps_kth) << e.name();
        }
    }
    EXPECT_TRUE(Estimator::named("classic").traits().photon_beams);
    EXPECT_TRUE(Estimator::named("corrected").traits().photon_beams);
    EXPECT_TRUE(Estimator::named("corrected").traits().leave_group_out);
    EXPECT_FALSE(Estimator::named("mse_optimal").traits().photon_beams);
}

// Distinct weights: which photon is dropped is visible in the value.
TEST(Estimators, ExactFormulasDropTheFarthest) {
    const double w[5] = {1, 2, 4, 8, 16};
    const double d2[5] = {0.01, 0.04, 0.09, 0.16, 0.25};
    const size_t k = 5;
    const double v = ball_volume(3, 0.5);
    EXPECT_DOUBLE_EQ(estimate_density(Estimator::named("classic"), w, d2, 5, false, k, kInfinity, 3).value, 31.0 / v);
    EXPECT_DOUBLE_EQ(estimate_density(Estimator::named("corrected"), w, d2, 5, false, k, kInfinity, 3).value, 15.0 / v);
    EXPECT_DOUBLE_EQ(estimate_density(Estimator::named("mse_optimal"), w, d2, 5, false, k, kInfinity, 3).value,
                     15.0 * 3.0 / 4.0 / v);
    // 2D uses pi r^2
    EXPECT_DOUBLE_EQ(estimate_density(Estimator::named("corrected"), w, d2, 5, false, k, kInfinity, 2).value,
                     15.0 / (kPi * 0.25));
    // k smaller than the list: only the first k count, r = r_k
    const auto e3 = estimate_density(Estimator::named("corrected"), w, d2, 5, false, 3, kInfinity, 3);
    EXPECT_DOUBLE_EQ(e3.value, 3.0 / ball_volume(3, 0.3));
    EXPECT_EQ(e3.kind, EstimateCase::knn);
    // Rgb instantiation
    const Rgb wr[3] = {Rgb(1, 2, 3), Rgb(1, 2, 3), Rgb(5, 5, 5)};
    const auto er = estimate_density<Rgb>(Estimator::named("corrected"), wr, d2, 3, true, 3, kInfinity, 3);
    EXPECT_TRUE(er.value.isApprox(Rgb(2, 4, 6) / ball_volume(3, 0.3)));
}

// Rule (a): fewer than k within a finite max radius -> all found / V(R), nothing dropped.
TEST(Estimators, RuleA_FixedRadius) {
    const double w[3] = {1, 2, 4};
    const double d2[3] = {0.01, 0.04, 0.09};
    EstimatorStats st;
    for (const Estimator& e : Estimator::all()) {
        const auto r = estimate_density(e, w, d2, 3, true, 5, 0.5, 3, &st);
        EXPECT_EQ(r.kind, EstimateCase::fixed_radius);
        EXPECT_DOUBLE_EQ(r.value, 7.0 / ball_volume(3, 0.5));
        EXPECT_DOUBLE_EQ(r.radius, 0.5);
    }
    EXPECT_EQ(st.fixed_radius, 3u);
    const auto none = estimate_density(Estimator::named("corrected"), w, d2, 0, true, 5, 0.5, 3, &st);
    EXPECT_EQ(none.kind, EstimateCase::empty);
    EXPECT_EQ(none.value, 0.0);
    EXPECT_EQ(st.empty, 1u);
}

// Rule (a) in combination: "corrected if r_k <= R else fixed radius R" is exactly unbiased
// (binomial or Poisson points), while R is chosen so that both branches happen often.
TEST(Estimators, RuleA_CorrectedWithMaxRadiusIsUnbiased) {
    const size_t n = 400, k = 10, T = 20000;
    const double R = std::cbrt(double(k) / double(n));   // E[count in B(R)] = k
    const double phi = ball_volume(3, 1.0) / double(n);   // truth 1
    EstimatorStats st;
    double sum = 0, sum2 = 0;
    std::vector<double> d2(n), w(k), dk(k);
    for (size_t t = 0; t < T; ++t) {
        Rng rng(mix64(99 ^ mix64(t)), t);
        for (size_t i = 0; i < n; ++i) d2[i] = sample_uniform_ball(rng.uniform(), rng.uniform(), rng.uniform()).squaredNorm();
        std::nth_element(d2.begin(), d2.begin() + (k - 1), d2.end());
        std::sort(d2.begin(), d2.begin() + k);
        size_t found = 0;
        for (size_t i = 0; i < k; ++i)
            if (d2[i] <= R * R) dk[found] = d2[i], w[found] = phi, ++found;
        const double v =
            estimate_density(Estimator::named("corrected"), w.data(), dk.data(), found, found < k, k, R, 3, &st).value;
        sum += v;
        sum2 += v * v;
    }
    const double mean = sum / T, se = std::sqrt((sum2 / T - mean * mean) / T);
    EXPECT_NEAR(mean, 1.0, 3.0 * se) << "se " << se;
    EXPECT_GT(st.fixed_radius, T / 5);
    EXPECT_GT(st.knn, T / 5);
}

// Rule (b): no max radius, fewer than k photons in total -> k' = count.
TEST(Estimators, RuleB_AllPhotons) {
    const double w[4] = {1, 2, 4, 8};
    const double d2[4] = {0.01, 0.04, 0.09, 0.16};
    EstimatorStats st;
    const double v4 = ball_volume(3, 0.4);
    auto c = estimate_density(Estimator::named("classic"), w, d2, 4, true, 8, kInfinity, 3, &st);
    EXPECT_EQ(c.kind, EstimateCase::all_photons);
    EXPECT_EQ(c.k_used, 4u);
    EXPECT_DOUBLE_EQ(c.value, 15.0 / v4);
    EXPECT_DOUBLE_EQ(estimate_density(Estimator::named("corrected"), w, d2, 4, true, 8, kInfinity, 3).value, 7.0 / v4);
    EXPECT_DOUBLE_EQ(estimate_density(Estimator::named("mse_optimal"), w, d2, 4, true, 8, kInfinity, 3).value,
                     7.0 * 2.0 / 3.0 / v4);
    auto one = estimate_density(Estimator::named("corrected"), w, d2, 1, true, 8, kInfinity, 3, &st);
    EXPECT_EQ(one.kind, EstimateCase::insufficient);
    EXPECT_EQ(one.value, 0.0);
    auto two = estimate_density(Estimator::named("mse_optimal"), w, d2, 2, true, 8, kInfinity, 3, &st);
    EXPECT_EQ(two.kind, EstimateCase::insufficient);
    auto classic_one = estimate_density(Estimator::named("classic"), w, d2, 1, true, 8, kInfinity, 3, &st);
    EXPECT_EQ(classic_one.kind, EstimateCase::insufficient);   // classic needs k >= 2 like corrected
    EXPECT_EQ(classic_one.value, 0.0);
    EXPECT_EQ(st.all_photons, 1u);
    EXPECT_EQ(st.insufficient, 3u);
    // an incomplete list with fewer than k is a caller error
    EXPECT_THROW(estimate_density(Estimator::named("classic"), w, d2, 4, false, 8, kInfinity, 3), Error);
}

// Rule (c): r_k = 0 -> extend to the first strictly farther photon; never Inf/NaN.
TEST(Estimators, RuleC_CoincidentPhotons) {
    const double w[6] = {1, 1, 1, 1, 2, 4};
    const double d2[6] = {0, 0, 0, 0, 0.25, 1.0};
    EstimatorStats st;
    const double v = ball_volume(3, 0.5);
    auto c = estimate_density(Estimator::named("classic"), w, d2, 6, true, 2, kInfinity, 3, &st);
    EXPECT_EQ(c.kind, EstimateCase::extended);
    EXPECT_EQ(c.k_used, 5u);
    EXPECT_DOUBLE_EQ(c.radius, 0.5);
    EXPECT_DOUBLE_EQ(c.value, 6.0 / v);
    auto k1 = estimate_density(Estimator::named("corrected"), w, d2, 6, true, 3, kInfinity, 3, &st);
    EXPECT_DOUBLE_EQ(k1.value, 4.0 / v);   // all coincident kept, the farther one dropped
    EXPECT_EQ(st.extended, 2u);
    // nothing farther in the list but more exist: ask for more
    auto more = estimate_density(Estimator::named("corrected"), w, d2, 4, false, 3, kInfinity, 3, &st);
    EXPECT_EQ(more.kind, EstimateCase::need_more);
    // nothing farther at all: degenerate 0 (no max radius) or fixed radius (with one)
    auto deg = estimate_density(Estimator::named("corrected"), w, d2, 4, true, 3, kInfinity, 3, &st);
    EXPECT_EQ(deg.kind, EstimateCase::degenerate);
    EXPECT_EQ(deg.value, 0.0);
    EXPECT_EQ(st.degenerate, 1u);
    auto fx = estimate_density(Estimator::named("corrected"), w, d2, 4, true, 3, 0.1, 3, &st);
    EXPECT_EQ(fx.kind, EstimateCase::fixed_radius);
    EXPECT_DOUBLE_EQ(fx.value, 4.0 / ball_volume(3, 0.1));
    // V(r_k) underflows to 0 although r_k > 0: treated like r_k = 0
    const double tiny[3] = {1e-240, 1e-240, 1e-2};
    auto u = estimate_density(Estimator::named("classic"), w, tiny, 3, true, 2, kInfinity, 3, &st);
    EXPECT_EQ(u.kind, EstimateCase::extended);
    EXPECT_TRUE(std::isfinite(u.value));
    // max radius 0
    auto z = estimate_density(Estimator::named("classic"), w, d2, 4, true, 8, 0.0, 3, &st);
    EXPECT_TRUE(std::isfinite(z.value));
}

TEST(Estimators, RuleC_ThroughPhotonMap) {
    std::vector<PhotonInput> in;
    Rng rng(5, 0);
    const Vec3 site(0.3, 0.3, 0.3);
    for (int i = 0; i < 50; ++i) in.push_back({site, Vec3::UnitZ(), Rgb::Constant(1.0)});
    for (int i = 0; i < 30; ++i)
        in.push_back({Vec3(rng.uniform(), rng.uniform(), rng.uniform()) + Vec3::Constant(2.0), Vec3::UnitZ(),
                      Rgb::Constant(1.0)});
    const PhotonMap map(in);
    GatherBuffers buf;
    EstimatorStats st;
    const auto r = estimate_in_scattering(map, site, Vec3::UnitZ(), 0.0, Estimator::named("corrected"), 8, kInfinity, buf, &st);
    EXPECT_EQ(r.kind, EstimateCase::extended);
    EXPECT_EQ(r.k_used, 51u);
    EXPECT_TRUE(all_finite(r.value));
    EXPECT_NEAR(r.value[0], 50.0 * kInv4Pi / ball_volume(3, r.radius), 1e-12 * r.value[0]);
    EXPECT_EQ(st.extended, 1u);
}

TEST(Estimators, InScatteringMatchesManualSum) {
    Rng rng(8, 0);
    std::vector<PhotonInput> in(3000);
    for (auto& p : in) {
        p.position = Vec3(rng.uniform(), rng.uniform(), rng.uniform());
        p.direction = sample_uniform_sphere(rng.uniform(), rng.uniform());
        p.power = Rgb(rng.uniform(), rng.uniform(), rng.uniform()) * 1e-3;
    }
    const PhotonMap map(in);
    GatherBuffers buf;
    NeighbourList nl;
    const Vec3 x(0.5, 0.4, 0.6), wo = Vec3(1, 2, 3).normalized();
    const double g = 0.6;
    for (const Estimator& e : Estimator::all()) {
        const auto r = estimate_in_scattering(map, x, wo, g, e, 20, kInfinity, buf);
        map.knn(x, 20, kInfinity, nl);
        Rgb s = Rgb::Zero();
        const size_t m = e == Estimator::named("classic") ? 20 : 19;
        for (size_t i = 0; i < m; ++i) s += hg_eval(nl[i].direction.dot(wo), g) * nl[i].power;
        if (e == Estimator::named("mse_optimal")) s *= 18.0 / 19.0;
        EXPECT_TRUE(r.value.isApprox(s / ball_volume(3, std::sqrt(nl[19].d2)), 1e-12)) << e.name();
    }
}

// ---- Monte Carlo against order statistics ------------------------------------------------------
namespace {

struct McResult {
    double mean = 0;
    size_t trials = 0;
};

// Uniform points in the unit disc/ball, query at the centre, truth 1. variant selects a wrong
// estimator for the rejection test: 0 real, 1 corrected with r_{k-1}, 2 classic with pi r^2 in 3D.
std::vector<std::vector<McResult>> monte_carlo(int dim, const std::vector<size_t>& ks, size_t n, size_t T,
                                               uint64_t seed, int variant = 0) {
    const size_t kmax = ks.back();
    const double phi = ball_volume(dim, 1.0) / double(n);
    std::vector<std::vector<McResult>> out(ks.size(), std::vector<McResult>(3));
    std::vector<double> d2(n), w(kmax, phi);
    for (size_t t = 0; t < T; ++t) {
        Rng rng(mix64(seed ^ mix64(t)), t);
        for (size_t i = 0; i < n; ++i) {
            if (dim == 2)
                d2[i] = sample_uniform_disc(rng.uniform(), rng.uniform()).squaredNorm();
            else
                d2[i] = sample_uniform_ball(rng.uniform(), rng.uniform(), rng.uniform()).squaredNorm();
        }
        std::nth_element(d2.begin(), d2.begin() + (kmax - 1), d2.end());
        std::sort(d2.begin(), d2.begin() + kmax);
        for (size_t ki = 0; ki < ks.size(); ++ki)
            for (size_t ei = 0; ei < 3; ++ei) {
                const Estimator e = Estimator::all()[ei];
                const size_t k = ks[ki];
                double v;
                if (variant == 1)   // wrong: radius r_{k-1}
                    v = estimate_corrected<double>({w.data(), d2.data(), k, std::sqrt(d2[k - 2]),
                                                    ball_volume(dim, std::sqrt(d2[k - 2])), dim});
                else if (variant == 2)   // wrong: pi r^2 in 3D
                    v = estimate_classic<double>({w.data(), d2.data(), k, std::sqrt(d2[k - 1]),
                                                  ball_volume(2, std::sqrt(d2[k - 1])), dim});
                else
                    v = estimate_density(e, w.data(), d2.data(), kmax, false, k, kInfinity, dim).value;
                out[ki][ei].mean += v;
            }
    }
    for (auto& row : out)
        for (auto& c : row) c.mean /= double(T), c.trials = T;
    return out;
}

// Exact finite-n standard error of the mean (variance from Beta(k, n-k+1) order statistics).
double exact_se(Estimator e, size_t k, size_t n, size_t T) {
    const double kk = double(k);
    const double corrected_var = (double(n) - kk + 1.0) / (double(n) * (kk - 2.0));
    double var = corrected_var;
    if (e == Estimator::named("classic")) var = kk * kk / ((kk - 1) * (kk - 1)) * corrected_var;
    if (e == Estimator::named("mse_optimal")) var = (kk - 2) * (kk - 2) / ((kk - 1) * (kk - 1)) * corrected_var;
    return std::sqrt(var / double(T));
}

const size_t kN = 500, kT = 10000;

}  // namespace

TEST(EstimatorsMonteCarlo, Ball3D) {
    const std::vector<size_t> ks = {3, 8, 32, 128};
    const auto mc = monte_carlo(3, ks, kN, kT, 2013);
    for (size_t ki = 0; ki < ks.size(); ++ki) {
        const double k = double(ks[ki]);
        EXPECT_NEAR(mc[ki][0].mean, k / (k - 1), 3 * exact_se(Estimator::named("classic"), ks[ki], kN, kT)) << "k=" << k;
        EXPECT_NEAR(mc[ki][1].mean, 1.0, 3 * exact_se(Estimator::named("corrected"), ks[ki], kN, kT)) << "k=" << k;
        EXPECT_NEAR(mc[ki][2].mean, (k - 2) / (k - 1), 3 * exact_se(Estimator::named("mse_optimal"), ks[ki], kN, kT));
    }
}

TEST(EstimatorsMonteCarlo, Disc2D) {
    const std::vector<size_t> ks = {3, 5, 10, 50};
    const auto mc = monte_carlo(2, ks, kN, kT, 2014);
    for (size_t ki = 0; ki < ks.size(); ++ki) {
        const double k = double(ks[ki]);
        EXPECT_NEAR(mc[ki][0].mean, k / (k - 1), 3 * exact_se(Estimator::named("classic"), ks[ki], kN, kT)) << "k=" << k;
        EXPECT_NEAR(mc[ki][1].mean, 1.0, 3 * exact_se(Estimator::named("corrected"), ks[ki], kN, kT)) << "k=" << k;
        EXPECT_NEAR(mc[ki][2].mean, (k - 2) / (k - 1), 3 * exact_se(Estimator::named("mse_optimal"), ks[ki], kN, kT));
    }
}

// The same tolerance rejects wrong variants by many standard errors. (Dropping the nearest
// instead of the farthest photon changes nothing for equal weights, so it cannot be seen in
// the mean: ExactFormulasDropTheFarthest checks it with distinct weights instead.)
TEST(EstimatorsMonteCarlo, WrongVariantsAreRejected) {
    const std::vector<size_t> ks = {3, 8, 32, 128};
    const auto wrong_radius = monte_carlo(3, ks, kN, kT, 2013, 1);
    const auto wrong_volume = monte_carlo(3, ks, kN, kT / 10, 2015, 2);
    for (size_t ki = 0; ki < ks.size(); ++ki) {
        const double se = exact_se(Estimator::named("corrected"), ks[ki], kN, kT);
        const double z = std::abs(wrong_radius[ki][0].mean - 1.0) / se;
        EXPECT_GT(z, 8.0) << "corrected with r_{k-1} not rejected at k=" << ks[ki] << " (z=" << z << ")";
        const double k = double(ks[ki]);
        const double se_c = exact_se(Estimator::named("classic"), ks[ki], kN, kT / 10);
        const double z2 = std::abs(wrong_volume[ki][0].mean - k / (k - 1)) / se_c;
        EXPECT_GT(z2, 8.0) << "pi r^2 in 3D not rejected at k=" << ks[ki] << " (z=" << z2 << ")";
    }
}
