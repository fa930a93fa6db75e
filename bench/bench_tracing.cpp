// Photon tracing through the default VDB medium (configs/default.toml: media/plume.vdb,
// sigma_t_scale 40), one thread, so the figures are per core.
//
//   BM_PhotonTrace          trace_photons() on 1 thread: real collisions/s (the full photon pass:
//                           light sampling, Embree floor hits, delta tracking, HG sampling, storing)
//   BM_FreeFlight           GridMedium::sample_free_flight() alone on rays from the spot light:
//                           real collisions/s and density lookups (tentative collisions)/s
//
// usage: bench_tracing [--benchmark_filter=...] [--benchmark_repetitions=N]
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include <filesystem>

#include "bench_common.h"
#include "core/rng.h"
#include "photon/photon_tracer.h"
#include "scene/grid_medium.h"
#include "scene/scene.h"

using namespace vpm;

namespace {

const Scene& default_scene() {
    static const std::unique_ptr<Scene> scene = Scene::load(bench::config_path("default.toml"));
    return *scene;
}

void BM_PhotonTrace(benchmark::State& state) {
    const Scene& scene = default_scene();
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    PhotonTraceSettings s;
    s.count = uint64_t(state.range(0));
    s.progress = false;
    uint64_t collisions = 0, stored = 0;
    for (auto _ : state) {
        const PhotonTraceResult r = trace_photons(scene, s);
        collisions += r.collisions;
        stored += r.photons.size();
        ++s.stream_offset;
    }
    state.counters["collisions/s"] = benchmark::Counter(double(collisions), benchmark::Counter::kIsRate);
    state.counters["paths/s"] =
        benchmark::Counter(double(s.count) * double(state.iterations()), benchmark::Counter::kIsRate);
    state.counters["collisions/path"] = double(collisions) / (double(s.count) * double(state.iterations()));
}
BENCHMARK(BM_PhotonTrace)->Arg(100000)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_FreeFlight(benchmark::State& state) {
    const Scene& scene = default_scene();
    const auto* medium = dynamic_cast<const GridMedium*>(scene.media.at(0).get());
    if (!medium) {
        state.SkipWithError("default scene has no grid medium");
        return;
    }
    // Rays from the spot light's position towards random points of the medium's bounds.
    const Vec3 origin(-1.6, 2.6, 1.2);
    const Bounds3 b = medium->bounds();
    Rng rng(7, 0);
    constexpr int kRays = 4096;
    std::vector<Ray> rays(kRays);
    for (auto& r : rays) {
        const Vec3 target(b.lo.x() + rng.uniform() * (b.hi.x() - b.lo.x()), b.lo.y() + rng.uniform() * (b.hi.y() - b.lo.y()),
                          b.lo.z() + rng.uniform() * (b.hi.z() - b.lo.z()));
        r = Ray{origin, (target - origin).normalized()};
    }
    TrackingStats st;
    int64_t real = 0, n = 0;
    for (auto _ : state) {
        for (const Ray& r : rays) {
            const double t = medium->sample_free_flight(r, kInfinity, rng, &st);
            real += t < kInfinity;
        }
        n += kRays;
    }
    state.counters["collisions/s"] = benchmark::Counter(double(real), benchmark::Counter::kIsRate);
    state.counters["lookups/s"] = benchmark::Counter(double(st.lookups), benchmark::Counter::kIsRate);
    state.counters["lookups/collision"] = real ? double(st.lookups) / double(real) : 0.0;
    state.counters["blocks/ray"] = double(st.blocks) / double(n);
}
BENCHMARK(BM_FreeFlight)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
