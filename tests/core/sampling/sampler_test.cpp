// The samplers' own properties (core/sampling/sampler.h): Sobol' matrices as Boost's engine makes them, the
// net properties that Owen scrambling keeps, stratum occupancy, uniform and mutually independent
// coordinates across sets (passes, seeds), the Rng binding, bad sizes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <vector>

#include <boost/random/sobol.hpp>

#include "core/error.h"
#include "core/sampling/hashed_permutation.h"
#include "core/sampling/owen_scramble.h"
#include "core/sampling/sampler.h"
#include "core/sampling/sampler_registry.h"
#include "core/sampling/sobol.h"

using namespace vpm;

namespace {

// True when the points (u, v) of `pts` (2^m of them) hold exactly one point in every elementary
// interval [i 2^-a, (i+1) 2^-a) x [j 2^-(m-a), (j+1) 2^-(m-a)), a = 0..m.
bool is_02_net(const std::vector<std::pair<double, double>>& pts, int m) {
    for (int a = 0; a <= m; ++a) {
        std::vector<int> count(size_t(1) << m, 0);
        for (const auto& p : pts) {
            const size_t i = size_t(p.first * double(1 << a)), j = size_t(p.second * double(1 << (m - a)));
            if (++count[(i << (m - a)) | j] > 1) return false;
        }
    }
    return true;
}

// One point per interval [i / n, (i + 1) / n).
bool is_stratified_1d(const std::vector<double>& us) {
    std::vector<int> count(us.size(), 0);
    for (double u : us)
        if (++count[size_t(u * double(us.size()))] > 1) return false;
    return true;
}

}  // namespace

TEST(Sobol, MatchesBoostEngineOnItsFirstPoints) {
    // Boost's engine skips point 0 and runs in Gray-code order: compare the sets of points 1 .. 2^m - 1.
    const int dims = 64, m = 10;
    boost::random::sobol engine(dims);
    std::set<std::vector<uint32_t>> boost_points, ours;
    for (uint32_t i = 1; i < (1u << m); ++i) {
        std::vector<uint32_t> p, q;
        for (int d = 0; d < dims; ++d) {
            p.push_back(uint32_t(engine() >> 32));
            q.push_back(sobol_bits(i, d));
        }
        boost_points.insert(p);
        ours.insert(q);
    }
    EXPECT_EQ(boost_points, ours);
    EXPECT_EQ(ours.size(), size_t((1u << m) - 1));
}

TEST(Sobol, FirstTwoDimensionsAre02NetsUnscrambledAndScrambled) {
    for (int m = 1; m <= 10; ++m) {
        const uint32_t n = 1u << m;
        for (uint32_t block = 0; block < 3; ++block) {   // every aligned block of 2^m points of a (0, 2)-sequence
            std::vector<std::pair<double, double>> pts;
            for (uint32_t i = block * n; i < (block + 1) * n; ++i)
                pts.emplace_back(sobol_bits(i, 0) * 0x1.0p-32, sobol_bits(i, 1) * 0x1.0p-32);
            EXPECT_TRUE(is_02_net(pts, m)) << "m " << m << " block " << block;
        }
        for (uint64_t key : {1ull, 2ull, 77ull}) {
            const PathSampler s(SamplerKind::sobol, key, n);
            std::vector<std::pair<double, double>> pts;
            for (uint32_t i = 0; i < n; ++i) pts.emplace_back(s.sample(i, 0), s.sample(i, 1));
            EXPECT_TRUE(is_02_net(pts, m)) << "scrambled, m " << m << " key " << key;
        }
    }
}

TEST(Sobol, EveryDimensionStratifiedIn1DIncludingPadded) {
    const int m = 8;
    const uint32_t n = 1u << m;
    const PathSampler s(SamplerKind::sobol, 12345, n);
    for (uint32_t d : {0u, 1u, 2u, 5u, 100u, 1023u, 1024u, 1025u, 3000u}) {
        std::vector<double> raw, scrambled;
        for (uint32_t i = 0; i < n; ++i) {
            if (d < uint32_t(kSobolDimensions)) raw.push_back(sobol_bits(i, int(d)) * 0x1.0p-32);
            scrambled.push_back(s.sample(i, d));
        }
        if (!raw.empty()) {
            EXPECT_TRUE(is_stratified_1d(raw)) << "dimension " << d;
        }
        EXPECT_TRUE(is_stratified_1d(scrambled)) << "scrambled dimension " << d;
    }
    // Padded dimension 1024 reads dimension 0's matrix at permuted indices: not the same values.
    int same = 0;
    for (uint32_t i = 0; i < n; ++i) same += s.sample(i, 0) == s.sample(i, 1024);
    EXPECT_LT(same, 4);
}

TEST(StratifiedSampler, EveryCellOfEveryPairHoldsOneSample) {
    for (uint64_t n : {1ull, 4ull, 8ull, 16ull, 32ull, 7ull, 4096ull, 1000ull}) {
        const PathSampler s(SamplerKind::stratified, 99 + n, n);
        // the grid: nx columns, ny rows with nx * ny >= n
        const uint64_t root = uint64_t(std::floor(std::sqrt(double(n))));
        uint64_t nx = root;
        while (nx > 1 && n % nx != 0) --nx;
        if (2 * nx < root) nx = root;
        nx = std::max<uint64_t>(nx, 1);
        const uint64_t ny = (n + nx - 1) / nx;
        for (uint32_t pair = 0; pair < 6; ++pair) {
            std::vector<int> count(nx * ny, 0);
            for (uint64_t i = 0; i < n; ++i) {
                const double u = s.sample(i, 2 * pair), v = s.sample(i, 2 * pair + 1);
                ASSERT_GE(u, 0.0);
                ASSERT_LT(u, 1.0);
                ASSERT_GE(v, 0.0);
                ASSERT_LT(v, 1.0);
                ++count[size_t(v * double(ny)) * nx + size_t(u * double(nx))];
            }
            EXPECT_EQ(*std::max_element(count.begin(), count.end()), 1) << "n " << n << " pair " << pair;
            EXPECT_EQ(uint64_t(std::count(count.begin(), count.end(), 1)), n);
        }
    }
}

TEST(HashedPermutation, IsABijectionForEverySize) {
    for (uint32_t n : {1u, 2u, 3u, 5u, 16u, 17u, 1000u, 4096u}) {
        for (uint64_t key : {0ull, 1ull, 0xdeadbeefull}) {
            std::vector<int> hit(n, 0);
            for (uint32_t i = 0; i < n; ++i) ++hit[permutation_element(i, n, key)];
            EXPECT_EQ(std::count(hit.begin(), hit.end(), 1), int(n)) << "n " << n;
        }
    }
}

// Over many sets (keys), a coordinate is uniform and unrelated to the same coordinate of a set with
// another pass or seed, and to the set's other dimensions: moments within 5 standard errors.
TEST(Samplers, CoordinatesUniformAndIndependentAcrossPassesAndSeeds) {
    const int sets = 40000;
    for (SamplerKind kind : {SamplerKind::independent, SamplerKind::stratified, SamplerKind::sobol}) {
        double mean = 0, mean2 = 0, cross_pass = 0, cross_seed = 0, cross_dim = 0;
        for (int k = 0; k < sets; ++k) {
            const PathSampler a(kind, sampler_key(1, 0, uint64_t(k), 7), 16);
            const PathSampler pass(kind, sampler_key(1, 1 << 20, uint64_t(k), 7), 16);
            const PathSampler seed(kind, sampler_key(2, 0, uint64_t(k), 7), 16);
            const double u = a.sample(5, 3) - 0.5;
            mean += u;
            mean2 += u * u;
            cross_pass += u * (pass.sample(5, 3) - 0.5);
            cross_seed += u * (seed.sample(5, 3) - 0.5);
            cross_dim += u * (a.sample(5, 2) - 0.5);
        }
        const double se_mean = std::sqrt(1.0 / 12.0 / sets), se_cross = (1.0 / 12.0) / std::sqrt(double(sets));
        const char* name = sampler_name(kind);
        EXPECT_LT(std::abs(mean / sets), 5 * se_mean) << name;
        EXPECT_LT(std::abs(mean2 / sets - 1.0 / 12.0), 5 * std::sqrt(1.0 / 180.0 / sets)) << name;
        EXPECT_LT(std::abs(cross_pass / sets), 5 * se_cross) << name;
        EXPECT_LT(std::abs(cross_seed / sets), 5 * se_cross) << name;
        EXPECT_LT(std::abs(cross_dim / sets), 5 * se_cross) << name;
    }
}

TEST(Samplers, SameKeyGivesTheSameVectors) {
    for (SamplerKind kind : {SamplerKind::independent, SamplerKind::stratified, SamplerKind::sobol}) {
        PathSampler a(kind, 5, 64), b(kind, 5, 64), c(kind, 6, 64);
        int differ = 0;
        for (uint32_t i = 0; i < 64; ++i)
            for (uint32_t d = 0; d < 40; ++d) {
                EXPECT_EQ(a.sample(i, d), b.sample(i, d));
                differ += a.sample(i, d) != c.sample(i, d);
            }
        EXPECT_GT(differ, 64 * 40 - 10) << sampler_name(kind);
    }
}

TEST(Samplers, BoundRngReadsDimensionsInOrderAndUnbindsToItsStream) {
    PathSampler s(SamplerKind::sobol, 3, 8);
    Rng bound(4, 5), plain(4, 5);
    bound.draw_from(&s);
    s.start_sample(6);
    for (uint32_t d = 0; d < 10; ++d) EXPECT_EQ(bound.uniform(), s.sample(6, d));
    EXPECT_EQ(s.dimensions_read(), 10u);
    bound.draw_from(nullptr);
    for (int i = 0; i < 10; ++i) EXPECT_EQ(bound.uniform(), plain.uniform());
}

TEST(Samplers, BadSetSizesAreErrors) {
    EXPECT_THROW(PathSampler(SamplerKind::sobol, 1, 0), Error);
    EXPECT_THROW(PathSampler(SamplerKind::sobol, 1, uint64_t(1) << 32), Error);
    EXPECT_THROW(PathSampler(SamplerKind::stratified, 1, (uint64_t(1) << 31) + 1), Error);
    EXPECT_NO_THROW(PathSampler(SamplerKind::sobol, 1, (uint64_t(1) << 32) - 1));
}

TEST(Samplers, RegistryNamesInOrder) {
    EXPECT_EQ(sampler_names(), (std::vector<std::string>{"independent", "stratified", "sobol"}));
    EXPECT_STREQ(sampler_name(SamplerKind::sobol), "sobol");
}

TEST(OwenScramble, UniformInEveryBitAtEveryDepth) {
    // One fixed value scrambled by many seeds: uniform on [0, 1) (mean 1/2, fraction below 1/4).
    for (int depth : {0, 1, 4, 20, 32}) {
        const int seeds = 40000;
        double mean = 0;
        int below_quarter = 0;
        for (int k = 0; k < seeds; ++k) {
            const double u = owen_scrambled_uniform(0x9abcdef0u, mix64(uint64_t(k)), depth);
            mean += u;
            below_quarter += u < 0.25;
        }
        EXPECT_LT(std::abs(mean / seeds - 0.5), 5 * std::sqrt(1.0 / 12.0 / seeds)) << depth;
        EXPECT_LT(std::abs(below_quarter / double(seeds) - 0.25), 5 * std::sqrt(0.1875 / seeds)) << depth;
    }
}

// What the sets are for: the mean of a smooth integrand over a set of 64 vectors varies far less
// than with independent vectors (variance ratios over 4000 sets; theory for jittered 2D: O(n^-2)).
TEST(Samplers, StratifiedAndSobolReduceTheVarianceOfASmoothIntegral) {
    auto variance = [](SamplerKind kind) {
        const int sets = 4000, n = 64;
        double sum = 0, sum2 = 0;
        for (int k = 0; k < sets; ++k) {
            const PathSampler s(kind, sampler_key(3, uint64_t(k), 0, 1), n);
            double m = 0;
            for (int i = 0; i < n; ++i) m += std::sin(3.0 * s.sample(uint64_t(i), 0)) * std::exp(s.sample(uint64_t(i), 1));
            m /= n;
            sum += m;
            sum2 += m * m;
        }
        return (sum2 - sum * sum / sets) / (sets - 1);
    };
    const double independent = variance(SamplerKind::independent);
    EXPECT_LT(variance(SamplerKind::stratified), 0.1 * independent);
    EXPECT_LT(variance(SamplerKind::sobol), 0.1 * independent);
}
