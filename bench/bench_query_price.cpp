// The kNN query's cost against the map's size, for the plan's price of a query
// (lib/render/plan/work_units.cpp). One thread, CPU time of the thread. Photons and query points are
// drawn with the density of media/blob.vdb (rejection against its maximum), as a photon pass and
// a march place them; each query is what the photon map integrator runs per used estimate:
// estimate_in_scattering with the corrected estimator, k = 32, gathering leave_half_out_gather(k)
// neighbours (photons.clustering = "leave_group_out", the default), HG weights at g = 0.
//
//   BM_QueryPrice/N     N stored photons (1e3 .. 4e6): ns per query (the time column / 4096)
//
// usage: bench_query_price [--benchmark_filter=...] [--benchmark_repetitions=N]
#include <benchmark/benchmark.h>

#include <vector>

#include "bench_common.h"
#include "core/sampling/rng.h"
#include "core/sampling/sampling.h"
#include "io/vdb_io.h"
#include "photon/estimate/estimators.h"
#include "photon/estimate/group_estimate.h"
#include "photon/map/photon_map.h"

using namespace vpm;

namespace {

constexpr int kQueries = 4096;

const DensityGrid& blob() {
    static const DensityGrid g = load_vdb_density(bench::config_path("../media/blob.vdb"));
    return g;
}

// n index-space points with the blob's density.
std::vector<Vec3> blob_points(size_t n, Rng& rng) {
    const DensityGrid& g = blob();
    const Bounds3 b = g.index_bounds();
    const double top = g.max_density();
    std::vector<Vec3> out;
    out.reserve(n);
    while (out.size() < n) {
        const Vec3 p(b.lo.x() + rng.uniform() * (b.hi.x() - b.lo.x()), b.lo.y() + rng.uniform() * (b.hi.y() - b.lo.y()),
                     b.lo.z() + rng.uniform() * (b.hi.z() - b.lo.z()));
        if (rng.uniform() * top < g.density(p)) out.push_back(p);
    }
    return out;
}

void BM_QueryPrice(benchmark::State& state) {
    const size_t n = size_t(state.range(0));
    Rng rng(22, 2);
    std::vector<PhotonInput> photons(n);
    const std::vector<Vec3> at = blob_points(n, rng);
    for (size_t i = 0; i < n; ++i) {
        photons[i].position = at[i];
        const double u1 = rng.uniform(), u2 = rng.uniform();
        photons[i].direction = sample_uniform_sphere(u1, u2);
        photons[i].power = Rgb::Constant(1.0 / double(n));
    }
    const PhotonMap map(photons);
    const std::vector<Vec3> queries = blob_points(kQueries, rng);
    const Estimator e = Estimator::named("corrected");
    const size_t k = 32;
    GatherBuffers buf;
    double sink = 0.0;
    for (auto _ : state)
        for (const Vec3& x : queries)
            sink += estimate_in_scattering(map, x, Vec3::UnitZ(), 0.0, e, k, kInfinity, buf, nullptr, leave_half_out_gather(k)).value[1];
    benchmark::DoNotOptimize(sink);
    state.counters["ns/query"] =
        benchmark::Counter(double(state.iterations()) * kQueries, benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_QueryPrice)->RangeMultiplier(4)->Range(1024, 4 << 20)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
