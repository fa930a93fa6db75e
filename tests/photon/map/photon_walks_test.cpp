// The walk of every stored photon (PhotonMap::walk) and the walk-neighbour query
// (PhotonMap::knn_walks) against brute force; the tracer's walk labels on any thread count.
#include <gtest/gtest.h>

#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "core/sampling/rng.h"
#include "core/sampling/sampling.h"
#include "photon/map/photon_map.h"
#include "photon/map/walk_group_split.h"
#include "photon/trace/photon_tracer.h"
#include "render/run/run_config.h"

using namespace vpm;

namespace {

// Walks of 1..6 photons, each photon within ~0.05 of the previous one, in the unit cube; photon i
// has a distinct x offset so that its input index can be read back from the stored position.
std::vector<PhotonInput> clustered_walks(size_t walks, uint64_t seed, bool shuffled_labels) {
    Rng rng(seed, 0);
    std::vector<PhotonInput> in;
    std::vector<uint64_t> labels(walks);
    for (size_t w = 0; w < walks; ++w) labels[w] = 3 * w + 7;   // gaps: labels are not ids
    if (shuffled_labels)
        for (size_t w = walks; w > 1; --w) std::swap(labels[w - 1], labels[rng.uniform_index(uint32_t(w))]);
    for (size_t w = 0; w < walks; ++w) {
        Vec3 x(rng.uniform(), rng.uniform(), rng.uniform());
        const int n = 1 + int(rng.uniform_index(6));
        for (int j = 0; j < n; ++j) {
            PhotonInput p;
            p.position = x;
            p.direction = sample_uniform_sphere(rng.uniform(), rng.uniform());
            p.power = Rgb::Constant(1.0);
            p.walk = labels[w];
            p.group = uint8_t(labels[w] % kWalkGroups);
            in.push_back(p);
            x += 0.05 * sample_uniform_sphere(rng.uniform(), rng.uniform());
        }
    }
    return in;
}

// Stored index -> input index, by exact position (the inputs' positions are distinct).
std::vector<size_t> input_index(const PhotonMap& map, const std::vector<PhotonInput>& in) {
    std::vector<std::pair<std::array<float, 3>, size_t>> keys;
    for (size_t i = 0; i < in.size(); ++i) {
        const Vec3 rel = in[i].position - map.centre();
        keys.push_back({{float(rel[0]), float(rel[1]), float(rel[2])}, i});
    }
    std::sort(keys.begin(), keys.end());
    std::vector<size_t> out(map.size());
    for (size_t s = 0; s < map.size(); ++s) {
        const Photon& p = map.record(s);
        const std::array<float, 3> key{p.p[0], p.p[1], p.p[2]};
        auto it = std::lower_bound(keys.begin(), keys.end(), std::make_pair(key, size_t(0)));
        EXPECT_TRUE(it != keys.end() && it->first == key);
        out[s] = it->second;
    }
    return out;
}

void expect_walks_follow_labels(bool shuffled) {
    const std::vector<PhotonInput> in = clustered_walks(300, shuffled ? 5 : 4, shuffled);
    const PhotonMap map(in);
    ASSERT_EQ(map.size(), in.size());
    EXPECT_EQ(map.walk_count(), 300u);
    const std::vector<size_t> origin = input_index(map, in);
    for (size_t a = 0; a < map.size(); ++a) {
        ASSERT_LT(map.walk(a), map.walk_count());
        EXPECT_EQ(walk_group(map.record(a).reserved), in[origin[a]].group);
        for (size_t b = a + 1; b < map.size(); b += 7) {   // ids are equal iff labels are, ordered alike
            const uint64_t la = in[origin[a]].walk, lb = in[origin[b]].walk;
            EXPECT_EQ(map.walk(a) == map.walk(b), la == lb);
            EXPECT_EQ(map.walk(a) < map.walk(b), la < lb);
        }
    }
}

// Brute force: every photon sorted by (double distance, stored index), up to and including the
// first photon of the k-th distinct walk.
std::vector<uint32_t> brute_walks(const PhotonMap& map, const Vec3& q, size_t k, double max_radius) {
    std::vector<std::pair<double, uint32_t>> all;
    const Vec3 rel = q - map.centre();
    for (size_t i = 0; i < map.size(); ++i) {
        const Photon& p = map.record(i);
        const double d2 = (rel - Vec3(p.p[0], p.p[1], p.p[2])).squaredNorm();
        if (d2 <= max_radius * max_radius) all.push_back({d2, uint32_t(i)});
    }
    std::sort(all.begin(), all.end());
    std::vector<uint32_t> out;
    std::set<uint32_t> seen;
    for (const auto& [d2, i] : all) {
        out.push_back(i);
        seen.insert(map.walk(i));
        if (seen.size() == k) break;
    }
    return out;
}

}  // namespace

TEST(PhotonWalks, WalkIdsFollowTheLabels) { expect_walks_follow_labels(false); }
TEST(PhotonWalks, WalkIdsFollowShuffledLabels) { expect_walks_follow_labels(true); }

TEST(PhotonWalks, KnnWalksMatchesBruteForce) {
    const std::vector<PhotonInput> in = clustered_walks(3000, 9, false);
    const PhotonMap map(in);
    Rng rng(10, 0);
    NeighbourList list;
    for (size_t k : {1u, 2u, 8u, 32u, 100u}) {
        for (int q = 0; q < 40; ++q) {
            const Vec3 x(rng.uniform(), rng.uniform(), rng.uniform());
            const double max_radius = q % 4 == 3 ? 0.05 : kInfinity;
            size_t walks = 0;
            map.knn_walks(x, k, max_radius, list, walks);
            const std::vector<uint32_t> ref = brute_walks(map, x, k, max_radius);
            ASSERT_EQ(list.size(), ref.size()) << "k " << k << " query " << q;
            std::set<uint32_t> distinct;
            for (size_t i = 0; i < ref.size(); ++i) {
                EXPECT_EQ(list[i].index, ref[i]);
                EXPECT_EQ(list[i].walk, map.walk(ref[i]));
                distinct.insert(list[i].walk);
            }
            EXPECT_EQ(walks, distinct.size());
            if (walks == k) {   // the last photon opens the k-th walk: no earlier photon of its walk
                for (size_t i = 0; i + 1 < list.size(); ++i) EXPECT_NE(list[i].walk, list.items.back().walk);
            } else {
                EXPECT_TRUE(std::isfinite(max_radius));   // fewer walks only within a finite radius
                EXPECT_LT(walks, k);
            }
        }
    }
}

// knn_walks sizes its first photon gather from the earlier queries of the list (walk_gather_ratio)
// and gathers again when that held fewer than k walks: the guess changes the cost, never the list.
// Long walks of 40 photons at 0.002 apart pile many siblings into one ball, so a guess of one
// photon per walk must gather again (several times), and one of 50 over-gathers.
TEST(PhotonWalks, KnnWalksDoesNotDependOnTheGatherGuess) {
    Rng rng(12, 0);
    std::vector<PhotonInput> in;
    for (uint64_t w = 0; w < 200; ++w) {
        Vec3 x(rng.uniform(), rng.uniform(), rng.uniform());
        for (int j = 0; j < 40; ++j) {
            PhotonInput p;
            p.position = x;
            p.direction = Vec3::UnitZ();
            p.power = Rgb::Constant(1.0);
            p.walk = w;
            in.push_back(p);
            x += 0.002 * sample_uniform_sphere(rng.uniform(), rng.uniform());
        }
    }
    const PhotonMap map(in);
    NeighbourList list;
    for (size_t k : {1u, 4u, 16u, 64u}) {
        for (int q = 0; q < 20; ++q) {
            // half the queries on a stored photon: its walk's siblings crowd the ball
            const Vec3 x = q % 2 ? map.position(rng.uniform_index(uint32_t(map.size())))
                                 : Vec3(rng.uniform(), rng.uniform(), rng.uniform());
            const std::vector<uint32_t> ref = brute_walks(map, x, k, kInfinity);
            for (double guess : {1.0, 50.0}) {
                list.walk_gather_ratio = guess;
                size_t walks = 0;
                ASSERT_EQ(map.knn_walks(x, k, kInfinity, list, walks), ref.size()) << "k " << k << " guess " << guess;
                EXPECT_EQ(walks, k);
                for (size_t i = 0; i < ref.size(); ++i) EXPECT_EQ(list[i].index, ref[i]);
            }
        }
    }
}

TEST(PhotonWalks, AtMost32BytesPerPhotonWithTheWalks) {
    Rng rng(7, 0);
    std::vector<PhotonInput> in(1000000);
    for (size_t i = 0; i < in.size(); ++i) {
        in[i].position = Vec3(rng.uniform(), rng.uniform(), rng.uniform());
        in[i].power = Rgb::Constant(1.0);
        in[i].walk = i / 2;
    }
    const PhotonMap map(in);
    EXPECT_EQ(map.walk_count(), 500000u);
    const double per = double(map.memory_bytes()) / double(map.size());
    EXPECT_LE(per, 32.0) << "measured " << per << " bytes per photon";
}

namespace {

// A ball of fog (sigma_t 3, albedo 0.8, g 0.4) under a constant sky: walks of a few collisions.
std::unique_ptr<Scene> fog_ball_under_a_sky() {
    const std::string text = R"(
[camera]
position = [0, 0, 5]
look_at = [0, 0, 0]
[[lights]]
type = "environment"
radiance = 0.1
[[media]]
type = 'homogeneous'
shape = 'sphere'
radius = 1
sigma_t_scale = 3
g = 0.4
albedo = 0.8
)";
    return RunConfig::build(parse_config(text, "walks.toml", VPM_SOURCE_DIR "/configs")).scene;
}

}  // namespace

// The tracer labels every photon with its path index: one walk's photons are consecutive, a walk's
// label mod kWalkGroups is its group, the map holds exactly the walks that stored a volume photon,
// and all of it is the same on 1 and 2 threads (the batches are merged in order).
TEST(PhotonWalks, TracerLabelsWalksTheSameOnAnyThreadCount) {
    auto scene = fog_ball_under_a_sky();
    PhotonTraceSettings s;
    s.count = 70000;   // more than the first chunk of batches
    s.progress = false;
    s.store_surface = false;
    PhotonTraceResult one, two;
    tbb::task_arena(1).execute([&] { one = trace_photons(*scene, s); });
    tbb::task_arena(2).execute([&] { two = trace_photons(*scene, s); });
    ASSERT_EQ(one.photons.size(), two.photons.size());
    ASSERT_GT(one.photons.size(), 10000u);
    for (size_t i = 0; i < one.photons.size(); ++i) {
        ASSERT_EQ(one.photons[i].walk, two.photons[i].walk) << i;
        ASSERT_EQ(one.photons[i].group, one.photons[i].walk % kWalkGroups) << i;
        ASSERT_LT(one.photons[i].walk, s.count);
        if (i > 0) {
            ASSERT_LE(one.photons[i - 1].walk, one.photons[i].walk) << i;
        }
    }
    const PhotonMap a(one.photons), b(two.photons);
    EXPECT_EQ(a.walk_count(), one.storing_walks);
    ASSERT_EQ(a.size(), b.size());
    for (size_t i = 0; i < a.size(); ++i) ASSERT_EQ(a.walk(i), b.walk(i)) << i;
}

// Photon beams carry their walk as photons do: labels in path order and the same on 1 and 2
// threads; every volume photon (a collision) ends a flight of its own walk, the beam stored before
// it, so one walk's beams and photons form one chain.
TEST(PhotonWalks, TracerLabelsBeamsWithTheirWalk) {
    auto scene = fog_ball_under_a_sky();
    PhotonTraceSettings s;
    s.count = 20000;
    s.progress = false;
    s.store_surface = false;
    s.store_beams = true;
    PhotonTraceResult one, two;
    tbb::task_arena(1).execute([&] { one = trace_photons(*scene, s); });
    tbb::task_arena(2).execute([&] { two = trace_photons(*scene, s); });
    ASSERT_EQ(one.beams.size(), two.beams.size());
    ASSERT_GT(one.beams.size(), one.photons.size());
    ASSERT_GT(one.photons.size(), 10000u);
    for (size_t i = 0; i < one.beams.size(); ++i) {
        ASSERT_EQ(one.beams[i].walk, two.beams[i].walk) << i;
        ASSERT_LT(one.beams[i].walk, s.count);
        if (i > 0) {
            ASSERT_LE(one.beams[i - 1].walk, one.beams[i].walk) << i;
        }
    }
    // Walk through both lists in order: the beam before each photon is of its walk and ends where
    // the photon is, travelling its way.
    size_t b = 0;
    for (size_t i = 0; i < one.photons.size(); ++i) {
        const PhotonInput& p = one.photons[i];
        bool found = false;
        for (; b < one.beams.size() && one.beams[b].walk <= p.walk && !found; ++b) {
            const PhotonBeam& beam = one.beams[b];
            found = beam.walk == p.walk && (beam.origin + beam.length * beam.dir - p.position).norm() < 1e-9 &&
                    (beam.dir - p.direction).norm() < 1e-12;
        }
        ASSERT_TRUE(found) << "photon " << i << " of walk " << p.walk;
    }
}

// The pilot's split maps (walk_group_split.h) keep every photon's walk: each walk lands whole in one
// part, so the parts' walks add up to the map's.
TEST(PhotonWalks, SplitByWalkGroupKeepsTheWalks) {
    const std::vector<PhotonInput> in = clustered_walks(500, 12, false);
    const PhotonMap map(in);
    const std::vector<PhotonMap> parts = split_by_walk_group(map, 2);
    ASSERT_EQ(parts.size(), 2u);
    EXPECT_EQ(parts[0].walk_count() + parts[1].walk_count(), map.walk_count());
    EXPECT_EQ(parts[0].size() + parts[1].size(), map.size());
}
