// The renderer's beam gather (render/photon_map/gathers/point_beam_gather.h) in configs/thin_cube.toml (issue 22): the
// build of the per-photon radii and the disc BVH against the stored photon count, and the cost of
// one camera-segment query (BVH walk, sort by foot point, transmittance per interval, kernel,
// phase, albedo) against the photon discs it crosses, which beam_k sets (radius ~ k^(1/3)).
//
//   build/bench_beam_gather [--benchmark_filter=...]
#include <benchmark/benchmark.h>

#include <map>

#include "bench_common.h"
#include "core/sampling/rng.h"
#include "core/sampling/sampling.h"
#include "photon/trace/photon_tracer.h"
#include "render/photon_map/gathers/point_beam_gather.h"
#include "render/run/run_config.h"

using namespace vpm;

namespace {

const RunConfig& thin_cube() {
    static const RunConfig c = RunConfig::load(bench::config_path("thin_cube.toml"));
    return c;
}

// The thin cube's stored photons (multiple scattering only, as under direct = "nee") for `emitted` paths.
const PhotonMap& map(size_t emitted) {
    static std::map<size_t, PhotonMap> cache;
    auto it = cache.find(emitted);
    if (it != cache.end()) return it->second;
    PhotonTraceSettings ts;
    ts.count = emitted;
    ts.seed = 9;
    ts.progress = false;
    return cache.emplace(emitted, PhotonMap(trace_photons(*thin_cube().scene, ts).photons)).first->second;
}

void BM_BeamBuild(benchmark::State& state) {
    const PhotonMap& m = map(size_t(state.range(0)));
    PointBeamGatherStats s;
    for (auto _ : state) {
        const PointBeamGather beam(*thin_cube().scene, m, 32, Kernel::constant(), kInfinity, 2.0);
        s = beam.stats();
    }
    state.counters["stored"] = double(m.size());
    state.counters["radii_ms"] = 1e3 * s.radii_seconds;
    state.counters["bvh_ms"] = 1e3 * s.bvh_seconds;
    state.counters["bytes/photon"] = s.total_bytes_per_photon;
}

void BM_BeamQuery(benchmark::State& state) {
    const PhotonMap& m = map(1000000);
    const PointBeamGather beam(*thin_cube().scene, m, size_t(state.range(0)), Kernel::constant(), kInfinity, 2.0);
    const Camera& camera = thin_cube().scene->camera;
    Rng rng(5, uint64_t(state.range(0)));
    for (auto _ : state) {
        const Ray ray = camera.generate_ray(rng.uniform() * camera.width(), rng.uniform() * camera.height());
        benchmark::DoNotOptimize(beam.in_scattering(ray, kInfinity, 0, rng));
    }
    const PointBeamGatherStats s = beam.stats();
    state.counters["stored"] = double(m.size());
    state.counters["crossed/query"] = double(s.crossed) / double(std::max<uint64_t>(s.queries, 1));
}

}  // namespace

BENCHMARK(BM_BeamBuild)->Arg(100000)->Arg(1000000)->Arg(4000000)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(BM_BeamQuery)->Arg(8)->Arg(32)->Arg(128)->Unit(benchmark::kMicrosecond);
BENCHMARK_MAIN();
