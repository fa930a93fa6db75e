// PhotonMap kNN query and build times against a bare nanoflann loop over the same points.
// Not a test: prints figures. usage: bench_photon_map [max_points=1e6] [build_points=1e7]
//   kNN at 1e5 .. max_points (x10 steps; pass 1e7 for the full table, ~1 GB and a few minutes),
//   then one build of build_points photons (0: skip). 20000 uniform random queries per case.
//   Last, the walk-neighbour estimate (photons.neighbours = "walks") against the photon-neighbour
//   one, both corrected, on a map of random walks of albedo 0.5 (photon/estimate/walk_estimate.h).
// (a plain main() so that the numbers are one run, single thread, same queries for both.)
#include <nanoflann.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include <tbb/info.h>
#include <tbb/task_arena.h>

#include "core/progress.h"
#include "core/sampling/rng.h"
#include "core/sampling/sampling.h"
#include "core/henyey_greenstein.h"
#include "photon/estimate/estimators.h"
#include "photon/estimate/walk_estimate.h"
#include "photon/map/photon_map.h"
#include "walk_photons.h"

using namespace vpm;

namespace {

struct Cloud {
    std::vector<float> xyz;
    size_t kdtree_get_point_count() const { return xyz.size() / 3; }
    float kdtree_get_pt(uint32_t i, size_t d) const { return xyz[3 * i + d]; }
    template <class B>
    bool kdtree_get_bbox(B&) const { return false; }
};
using BareTree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, Cloud, float, uint32_t>,
                                                     Cloud, 3, uint32_t>;

std::vector<PhotonInput> make(size_t n, uint64_t seed) {
    Rng rng(seed, 0);
    std::vector<PhotonInput> v(n);
    for (auto& p : v) {
        p.position = Vec3(rng.uniform(), rng.uniform(), rng.uniform());
        p.direction = sample_uniform_sphere(rng.uniform(), rng.uniform());
        p.power = Rgb::Constant(1.0 / double(n));
    }
    return v;
}

}  // namespace

int main(int argc, char** argv) {
    const size_t max_n = argc > 1 ? size_t(std::atof(argv[1])) : 1000000;
    const size_t build_n = argc > 2 ? size_t(std::atof(argv[2])) : 10000000;
    const size_t Q = 20000;
    for (size_t n = 100000; n <= max_n; n *= 10) {
        const auto in = make(n, 1);
        Timer tb;
        const PhotonMap map(in);
        const double t_map = tb.seconds();
        Cloud cloud;
        cloud.xyz.reserve(3 * n);
        for (const auto& p : in)
            for (int a = 0; a < 3; ++a) cloud.xyz.push_back(float(p.position[a]));
        Cloud sorted;   // the same points in the map's stored (kd-tree leaf) order
        sorted.xyz.reserve(3 * n);
        for (size_t i = 0; i < n; ++i)
            for (int a = 0; a < 3; ++a) sorted.xyz.push_back(float(map.position(i)[a]));
        BareTree bare_sorted(3, sorted, nanoflann::KDTreeSingleIndexAdaptorParams(32));
        Timer tb2;
        BareTree bare(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(32));
        const double t_bare = tb2.seconds();
        std::printf("n=%zu  build: PhotonMap %.3f s (incl. Morton sort + encode), bare nanoflann %.3f s; "
                    "memory %.2f bytes/photon\n",
                    n, t_map, t_bare, double(map.memory_bytes()) / double(n));
        Rng rng(2, 0);
        std::vector<Vec3> qs(Q);
        for (auto& q : qs) q = Vec3(rng.uniform(), rng.uniform(), rng.uniform());
        for (size_t k : {8, 32, 128}) {
            NeighbourList nl;
            double sink = 0;
            Timer t1;
            for (const auto& q : qs) {
                map.knn(q, k, kInfinity, nl);
                sink += nl.items.back().d2;
            }
            const double us_map = t1.seconds() / Q * 1e6;
            std::vector<uint32_t> idx(k);
            std::vector<float> d2(k);
            Timer t2;
            for (const auto& q : qs) {
                const float qf[3] = {float(q.x()), float(q.y()), float(q.z())};
                nanoflann::KNNResultSet<float, uint32_t> rs(k);
                rs.init(idx.data(), d2.data());
                bare.findNeighbors(rs, qf, nanoflann::SearchParams());
                sink += d2[k - 1];
            }
            const double us_bare = t2.seconds() / Q * 1e6;
            Timer t3;
            for (const auto& q : qs) {
                const float qf[3] = {float(q.x()), float(q.y()), float(q.z())};
                nanoflann::KNNResultSet<float, uint32_t> rs(k);
                rs.init(idx.data(), d2.data());
                bare_sorted.findNeighbors(rs, qf, nanoflann::SearchParams());
                sink += d2[k - 1];
            }
            const double us_sorted = t3.seconds() / Q * 1e6;
            std::printf("  k=%3zu  PhotonMap::knn %.2f us/query | bare nanoflann: input order %.2f, stored order %.2f "
                        "us/query | ratio to the faster bare loop %.2f  [%g]\n",
                        k, us_map, us_bare, us_sorted, us_map / std::min(us_bare, us_sorted), sink > 0 ? 0.0 : 1.0);
        }
    }
    if (build_n > 0) {
        // The build on 1 thread and on all threads (the same tree: photon_map_test), interleaved
        // three times; the least time of each.
        const auto in = make(build_n, 3);
        const int all = tbb::info::default_concurrency();
        double best[2] = {1e30, 1e30};
        size_t bytes = 0;
        for (int rep = 0; rep < 3; ++rep)
            for (int t = 0; t < 2; ++t) {
                tbb::task_arena arena(t == 0 ? 1 : all);
                Timer tb;
                arena.execute([&] {
                    const PhotonMap map(in);
                    bytes = map.memory_bytes();
                });
                best[t] = std::min(best[t], tb.seconds());
            }
        std::printf("n=%zu  build: PhotonMap %.3f s on 1 thread, %.3f s on %d threads (%.2fx), memory %.2f bytes/photon (%.1f MB)\n",
                    build_n, best[0], best[1], all, best[0] / best[1], double(bytes) / double(build_n), bytes / 1e6);
    }
    {
        // Walks of albedo 0.5 (mean 2 photons, an Exp(1) flight apart) in a cube of side 20 mfp, 1e6
        // photons (~125 per mfp^3); the estimates at the same 20000 interior points, corrected over
        // photons and over walks, interleaved three times, the least time of each.
        Rng rng(5, 0);
        const std::vector<PhotonInput> in = bench::walk_photons(rng, 1000000, 20.0);
        const PhotonMap map(in);
        std::vector<Vec3> qs(Q);
        for (auto& q : qs) q = Vec3(2 + 16 * rng.uniform(), 2 + 16 * rng.uniform(), 2 + 16 * rng.uniform());
        const Estimator corrected = Estimator::named("corrected");
        for (size_t k : {8, 32}) {
            GatherBuffers buf;
            double best[2] = {1e30, 1e30}, sink = 0;
            for (int rep = 0; rep < 3; ++rep)
                for (int form = 0; form < 2; ++form) {
                    Timer t;
                    for (const auto& q : qs)
                        sink += (form == 0 ? estimate_in_scattering(map, q, Vec3::UnitZ(), 0.0, corrected, k, kInfinity, buf)
                                           : estimate_in_scattering_walks(map, q, Vec3::UnitZ(), 0.0, corrected, k, kInfinity, buf))
                                    .value[0];
                    best[form] = std::min(best[form], t.seconds());
                }
            std::printf("walks n=%zu (%zu walks)  k=%2zu  corrected estimate over photons %.2f us/query, over walks %.2f us/query: "
                        "walks / photons %.2fx  [%g]\n",
                        map.size(), map.walk_count(), k, best[0] / Q * 1e6, best[1] / Q * 1e6, best[1] / best[0], sink > 0 ? 0.0 : 1.0);
        }
    }
    return 0;
}
