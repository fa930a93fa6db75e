// Render of the default scene (configs/default.toml) with the photon map (corrected, k = 32,
// 1e5 photons, NEE for single scattering) and with the reference path tracer, at 128x128, 16 spp,
// on 1 and 2 threads (the speed-up is the ratio of the two real times).
//
//   BM_PhotonMapRender/T   run(): photon pass + kd-tree + render, T threads
//   BM_PathTraceRender/T   run() with the path tracer, T threads
//
// usage: bench_render [--benchmark_filter=...] [--benchmark_repetitions=N]
#include <benchmark/benchmark.h>
#include <ctime>
#include <tbb/global_control.h>

#include "bench_common.h"
#include "render/run/run.h"

using namespace vpm;

namespace {

const std::vector<std::string> kCommon = {"render.width=128", "render.height=128"};

void run_config(benchmark::State& state, const char* config, std::vector<std::string> sets) {
    for (const auto& s : kCommon) sets.push_back(s);
    const RunConfig loaded = RunConfig::load(bench::config_path(config), sets);
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(state.range(0)));
    RunOptions o;
    o.progress = false;
    double samples = 0, trace = 0, build = 0, render = 0;
    const std::clock_t cpu0 = std::clock();   // process CPU time, all threads
    for (auto _ : state) {
        const RunResult r = vpm::run(loaded, o);
        samples += double(r.stats.render.samples);
        trace += r.stats.seconds("trace");
        build += r.stats.seconds("build");
        render += r.stats.seconds("render");
        ++o.stream_offset;
    }
    const double it = double(state.iterations());
    // CPU seconds of all threads per iteration: with 2 threads on a machine that other processes
    // keep busy, the wall-clock speed-up is not measurable, but equal total CPU at 1 and 2 threads
    // says the parallel render adds no work (its speed-up on 2 idle cores is then bounded only by
    // the serial parts: photon-map kd-tree build and the scene load).
    state.counters["cpu_all_threads_s"] = double(std::clock() - cpu0) / CLOCKS_PER_SEC / it;
    state.counters["samples/s"] = benchmark::Counter(samples, benchmark::Counter::kIsRate);
    state.counters["trace_s"] = trace / it;
    state.counters["build_s"] = build / it;
    state.counters["render_s"] = render / it;
}

void BM_PhotonMapRender(benchmark::State& state) {
    run_config(state, "default_photon_map.toml", {"photons.count=100000", "render.spp=16"});
}
BENCHMARK(BM_PhotonMapRender)->Arg(1)->Arg(2)->Unit(benchmark::kSecond)->UseRealTime()->Iterations(2);

void BM_PathTraceRender(benchmark::State& state) { run_config(state, "default.toml", {"render.spp=16"}); }
BENCHMARK(BM_PathTraceRender)->Arg(1)->Arg(2)->Unit(benchmark::kSecond)->UseRealTime()->Iterations(2);

}  // namespace

BENCHMARK_MAIN();
