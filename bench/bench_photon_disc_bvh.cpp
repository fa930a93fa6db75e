// The beam estimate's building blocks against the photon count (issue 22): per-photon radii
// (photon_radii, kNN k = 32 for every photon), the photon-disc BVH build, and one beam query
// (a segment of length 0.4 through the centre of a uniform cloud in the unit ball) against a point
// kNN query at the same k, with the photons crossed per query and bytes per photon.
//
//   build/bench_photon_disc_bvh [--benchmark_filter=...]
#include <benchmark/benchmark.h>

#include <map>

#include "core/sampling/rng.h"
#include "core/sampling/sampling.h"
#include "photon/map/photon_disc_bvh.h"
#include "photon/map/photon_radii.h"

using namespace vpm;

namespace {

struct Cloud {
    PhotonMap map;
    std::vector<Vec3> centres;
    std::vector<double> radii;
};

const Cloud& cloud(size_t n) {
    static std::map<size_t, Cloud> cache;
    auto it = cache.find(n);
    if (it != cache.end()) return it->second;
    Rng rng(3, n);
    std::vector<PhotonInput> photons(n);
    for (PhotonInput& p : photons) {
        p.position = sample_uniform_ball(rng.uniform(), rng.uniform(), rng.uniform());
        p.power = Rgb::Ones();
    }
    Cloud c{PhotonMap(photons), {}, {}};
    c.radii = photon_radii(c.map, 32);
    for (size_t i = 0; i < c.map.size(); ++i) c.centres.push_back(c.map.position(i));
    return cache.emplace(n, std::move(c)).first->second;
}

void BM_PhotonRadii(benchmark::State& state) {
    const Cloud& c = cloud(size_t(state.range(0)));
    for (auto _ : state) benchmark::DoNotOptimize(photon_radii(c.map, 32));
    state.counters["photons/s"] = benchmark::Counter(double(c.map.size()), benchmark::Counter::kIsIterationInvariantRate);
}

void BM_DiscBvhBuild(benchmark::State& state) {
    const Cloud& c = cloud(size_t(state.range(0)));
    size_t bytes = 0;
    for (auto _ : state) {
        const PhotonDiscBvh bvh(c.centres, c.radii);
        bytes = bvh.memory_bytes();
    }
    state.counters["bytes/photon"] = double(bytes) / double(c.map.size());
    state.counters["kd-tree map bytes/photon"] = double(c.map.memory_bytes()) / double(c.map.size());
}

void BM_BeamQuery(benchmark::State& state) {
    const Cloud& c = cloud(size_t(state.range(0)));
    const PhotonDiscBvh bvh(c.centres, c.radii);
    Rng rng(5, 5);
    size_t crossed = 0, queries = 0;
    for (auto _ : state) {
        const Vec3 d = sample_uniform_sphere(rng.uniform(), rng.uniform());
        double sum = 0.0;
        bvh.for_each_crossed(-0.2 * d, d, 0.4, [&](uint32_t, double, double d2) {
            sum += d2;
            ++crossed;
        });
        benchmark::DoNotOptimize(sum);
        ++queries;
    }
    state.counters["crossed/query"] = double(crossed) / double(queries);
}

void BM_PointKnnQuery(benchmark::State& state) {
    const Cloud& c = cloud(size_t(state.range(0)));
    Rng rng(5, 6);
    NeighbourList list;
    for (auto _ : state) {
        const Vec3 x = 0.2 * sample_uniform_ball(rng.uniform(), rng.uniform(), rng.uniform());
        benchmark::DoNotOptimize(c.map.knn(x, 32, kInfinity, list));
    }
}

}  // namespace

BENCHMARK(BM_PhotonRadii)->Arg(100000)->Arg(1000000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DiscBvhBuild)->Arg(100000)->Arg(1000000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_BeamQuery)->Arg(100000)->Arg(1000000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_PointKnnQuery)->Arg(100000)->Arg(1000000)->Unit(benchmark::kMicrosecond);
BENCHMARK_MAIN();
