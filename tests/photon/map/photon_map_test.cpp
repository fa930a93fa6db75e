// kNN of the PhotonMap against brute force over the stored (decoded) photons.
#include <gtest/gtest.h>

#include <algorithm>

#include <cstring>
#include <tbb/task_arena.h>

#include "core/sampling/rng.h"
#include "core/sampling/sampling.h"
#include "core/error.h"
#include "photon/map/photon_map.h"

using namespace vpm;

namespace {

struct Ref {
    double d2;
    uint32_t index;
};

// Brute force over stored records with the map's own arithmetic (query relative to the centre).
std::vector<Ref> brute(const PhotonMap& map, const Vec3& q, size_t k, double max_radius) {
    std::vector<Ref> all;
    const Vec3 rel = q - map.centre();
    for (size_t i = 0; i < map.size(); ++i) {
        const Photon& p = map.record(i);
        const double d2 = (rel - Vec3(p.p[0], p.p[1], p.p[2])).squaredNorm();
        if (std::isfinite(max_radius) && d2 > max_radius * max_radius) continue;
        all.push_back({d2, uint32_t(i)});
    }
    std::sort(all.begin(), all.end(), [](const Ref& a, const Ref& b) {
        return a.d2 < b.d2 || (a.d2 == b.d2 && a.index < b.index);
    });
    if (all.size() > k) all.resize(k);
    return all;
}

void compare(const PhotonMap& map, const Vec3& q, size_t k, double max_radius, NeighbourList& nl) {
    const auto ref = brute(map, q, k, max_radius);
    const size_t found = map.knn(q, k, max_radius, nl);
    ASSERT_EQ(found, ref.size()) << "k=" << k << " R=" << max_radius;
    for (size_t i = 0; i < found; ++i) {
        // distances agree (the tree ranks in float; the kth may swap with a float-tie)
        ASSERT_NEAR(nl[i].d2, ref[i].d2, 1e-5 * ref[i].d2 + 1e-12) << "i=" << i << " k=" << k;
        if (i > 0) {
            ASSERT_LE(nl[i - 1].d2, nl[i].d2);
        }
    }
    // every neighbour strictly closer than the farthest reference one is found, by index
    if (found) {
        const double cut = ref.back().d2 * (1 - 1e-5);
        std::vector<uint32_t> a, b;
        for (const auto& r : ref)
            if (r.d2 < cut) a.push_back(r.index);
        for (const auto& n : nl.items)
            if (n.d2 < cut) b.push_back(n.index);
        std::sort(a.begin(), a.end());
        std::sort(b.begin(), b.end());
        ASSERT_EQ(a, b);
    }
    for (size_t i = 0; i < found; ++i) {   // decoded attributes are those of the record
        EXPECT_TRUE((nl[i].power == map.power(nl[i].index)).all());
        EXPECT_TRUE(nl[i].direction.isApprox(map.direction(nl[i].index)));
    }
}

}  // namespace

TEST(PhotonMap, KnnMatchesBruteForceUniform) {
    Rng rng(1, 0);
    std::vector<PhotonInput> in(20000);
    const Vec3 off(500.0, -20.0, 3.0);
    for (auto& p : in) {
        p.position = off + Vec3(rng.uniform(), rng.uniform(), rng.uniform());
        p.direction = sample_uniform_sphere(rng.uniform(), rng.uniform());
        p.power = Rgb(rng.uniform(), 1.0, 0.5);
    }
    const PhotonMap map(in);
    EXPECT_EQ(map.size(), in.size());
    NeighbourList nl;
    for (int q = 0; q < 60; ++q) {
        const Vec3 x = off + Vec3(rng.uniform(), rng.uniform(), rng.uniform()) * 1.2 - Vec3::Constant(0.1);
        for (size_t k : {1, 8, 50})
            for (double R : {kInfinity, 0.05, 0.2}) compare(map, x, k, R, nl);
    }
}

TEST(PhotonMap, KnnMatchesBruteForceClusteredWithDuplicates) {
    Rng rng(2, 0);
    std::vector<PhotonInput> in;
    std::vector<Vec3> sites;
    for (int s = 0; s < 40; ++s) sites.push_back(Vec3(rng.uniform(), rng.uniform(), rng.uniform()) * 10.0);
    for (int i = 0; i < 6000; ++i) {
        PhotonInput p;
        const Vec3& c = sites[rng.uniform_index(40)];
        const double u = rng.uniform();
        if (u < 0.4)
            p.position = c;   // exact duplicates: coincident photons
        else
            p.position = c + 0.05 * sample_uniform_ball(rng.uniform(), rng.uniform(), rng.uniform());
        p.power = Rgb::Constant(1.0 + rng.uniform());
        in.push_back(p);
    }
    const PhotonMap map(in);
    NeighbourList nl;
    for (int q = 0; q < 80; ++q) {
        Vec3 x = q % 2 ? sites[q % 40] : Vec3(rng.uniform(), rng.uniform(), rng.uniform()) * 10.0;
        for (size_t k : {1, 8, 64, 200})
            for (double R : {kInfinity, 0.01, 0.3}) compare(map, x, k, R, nl);
    }
}

TEST(PhotonMap, KLargerThanCountAndEmptyMap) {
    std::vector<PhotonInput> in(10);
    for (int i = 0; i < 10; ++i) in[i].position = Vec3(i, 0, 0), in[i].power = Rgb::Ones();
    const PhotonMap map(in);
    NeighbourList nl;
    EXPECT_EQ(map.knn(Vec3(2.2, 0, 0), 20, kInfinity, nl), 10u);
    EXPECT_NEAR(nl[0].d2, 0.04, 1e-9);
    EXPECT_NEAR(nl[9].d2, (9.0 - 2.2) * (9.0 - 2.2), 1e-4);
    compare(map, Vec3(2.2, 0, 0), 20, kInfinity, nl);
    compare(map, Vec3(2.2, 0, 0), 20, 1.5, nl);
    EXPECT_EQ(map.knn(Vec3(2.2, 0, 0), 20, 0.1, nl), 0u);
    EXPECT_EQ(map.knn(Vec3(2, 0, 0), 3, 1.0, nl), 3u);   // photons exactly at max_radius are included
    const PhotonMap empty(std::vector<PhotonInput>{});
    EXPECT_EQ(empty.knn(Vec3::Zero(), 5, kInfinity, nl), 0u);
    EXPECT_EQ(empty.memory_bytes(), 0u);
}

TEST(PhotonMap, RejectsNonFinitePositions) {
    std::vector<PhotonInput> in(3);
    in[1].position = Vec3(0, std::nan(""), 0);
    EXPECT_THROW(PhotonMap{in}, Error);
}

// Powers are stored as unsigned codes: a negative one is refused, not clamped to zero.
TEST(PhotonMap, RejectsNegativePower) {
    std::vector<PhotonInput> in(3);
    for (auto& p : in) p.power = Rgb(1, 1, 1);
    in[2].power = Rgb(1, -1e-9, 1);
    try {
        PhotonMap map(in);
        FAIL() << "a negative power was accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("photon 2 has negative power"), std::string::npos) << e.what();
    }
}

TEST(PhotonMap, RejectsALeafSizeOfZero) {
    std::vector<PhotonInput> in(3);
    for (auto& p : in) p.power = Rgb(1, 1, 1);
    EXPECT_THROW(PhotonMap(in, 0), Error);   // nanoflann's leaf_max_size 0 was clamped to 1 silently
    EXPECT_EQ(PhotonMap(in, 1).size(), 3u);
}

TEST(PhotonMap, TotalPowerAndBounds) {
    std::vector<PhotonInput> in(100);
    for (int i = 0; i < 100; ++i) in[i].position = Vec3(i, -i, 2 * i), in[i].power = Rgb(0.01, 0.02, 0.03);
    const PhotonMap map(in);
    EXPECT_TRUE(map.total_power().isApprox(Rgb(1, 2, 3), 1e-3));
    EXPECT_TRUE(map.bounds().lo.isApprox(Vec3(0, -99, 0)));
    EXPECT_TRUE(map.bounds().hi.isApprox(Vec3(99, 0, 198)));
}

// The kd-tree is built in parallel (photon_map.cpp) and the records then move into its leaf order:
// the stored records, walks and queries must be the same on any thread count, so that queries
// (and images) do not depend on the machine.
TEST(PhotonMap, ParallelBuildIsTheSameOnAnyThreadCount) {
    Rng rng(7, 0);
    std::vector<PhotonInput> in;
    std::vector<Vec3> sites;
    for (int s = 0; s < 50; ++s) sites.push_back(Vec3(rng.uniform(), rng.uniform(), rng.uniform()) * 10.0);
    for (int i = 0; i < 200000; ++i) {   // above the parallel threshold, with coincident photons
        PhotonInput p;
        const Vec3& c = sites[rng.uniform_index(50)];
        p.position = rng.uniform() < 0.2 ? c : c + 0.3 * sample_uniform_ball(rng.uniform(), rng.uniform(), rng.uniform());
        p.direction = sample_uniform_sphere(rng.uniform(), rng.uniform());
        p.power = Rgb::Constant(1.0 + rng.uniform());
        p.walk = uint64_t(i / 3);
        in.push_back(p);
    }
    PhotonMap one, four;
    tbb::task_arena(1).execute([&] { one = PhotonMap(in); });
    tbb::task_arena(4).execute([&] { four = PhotonMap(in); });
    ASSERT_EQ(one.size(), in.size());
    ASSERT_EQ(four.size(), in.size());
    size_t differing = 0;
    for (size_t i = 0; i < one.size(); ++i)
        differing += std::memcmp(&one.record(i), &four.record(i), sizeof(Photon)) != 0 || one.walk(i) != four.walk(i);
    EXPECT_EQ(differing, 0u);

    NeighbourList a, b;
    for (int q = 0; q < 200; ++q) {
        const Vec3 x = sites[size_t(q) % 50] + 0.2 * sample_uniform_ball(rng.uniform(), rng.uniform(), rng.uniform());
        one.knn(x, 32, kInfinity, a);
        four.knn(x, 32, kInfinity, b);
        ASSERT_EQ(a.size(), b.size());
        for (size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a[i].index, b[i].index);
    }
}
