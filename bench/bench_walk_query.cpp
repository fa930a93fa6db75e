// The walk-neighbour query (photons.neighbours = "walks", photon/estimate/walk_estimate.h) against the
// photon-neighbour query, both the corrected in-scattering estimate, on one map of 1e6 photons from
// random walks of albedo 0.5 (mean 2 photons a walk, an Exp(1) flight apart) in a cube of side 20 mfp
// (~125 photons per mfp^3), at the same 4096 interior points. One thread.
//
//   BM_CorrectedQuery/K/FORM   K = 8, 32, 128; FORM 0 = over photons, 1 = over walks: us per query
//
// The ratio walks / photons is what the target names (within 1.3x); take it from one run with
// interleaved repetitions, so that both forms see the same load:
//   bench_walk_query --benchmark_enable_random_interleaving=true --benchmark_repetitions=10 \
//     --benchmark_format=json > out.json && python3 bench/walk_query_ratio.py out.json
#include <benchmark/benchmark.h>

#include <cmath>
#include <vector>

#include "core/sampling/rng.h"
#include "core/sampling/sampling.h"
#include "photon/estimate/estimators.h"
#include "photon/estimate/walk_estimate.h"
#include "photon/map/photon_map.h"
#include "walk_photons.h"

using namespace vpm;

namespace {

constexpr int kQueries = 4096;

struct WalkScene {
    PhotonMap map;
    std::vector<Vec3> queries;
};

const WalkScene& scene() {
    static const WalkScene s = [] {
        Rng rng(5, 0);
        const std::vector<PhotonInput> in = bench::walk_photons(rng, 1000000, 20.0);
        WalkScene out{PhotonMap(in), std::vector<Vec3>(kQueries)};
        for (auto& q : out.queries) q = Vec3(2 + 16 * rng.uniform(), 2 + 16 * rng.uniform(), 2 + 16 * rng.uniform());
        return out;
    }();
    return s;
}

void BM_CorrectedQuery(benchmark::State& state) {
    const WalkScene& s = scene();
    const size_t k = size_t(state.range(0));
    const bool walks = state.range(1) != 0;
    const Estimator corrected = Estimator::named("corrected");
    GatherBuffers buf;
    double sink = 0.0;
    for (auto _ : state)
        for (const Vec3& q : s.queries)
            sink += (walks ? estimate_in_scattering_walks(s.map, q, Vec3::UnitZ(), 0.0, corrected, k, kInfinity, buf)
                           : estimate_in_scattering(s.map, q, Vec3::UnitZ(), 0.0, corrected, k, kInfinity, buf))
                        .value[0];
    benchmark::DoNotOptimize(sink);
    state.counters["us/query"] = benchmark::Counter(double(state.iterations()) * kQueries * 1e-6,
                                                    benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_CorrectedQuery)
    ->ArgNames({"k", "walks"})
    ->ArgsProduct({{8, 32, 128}, {0, 1}})
    ->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
