// Photon tracing through the default VDB medium (configs/default.toml: media/plume.vdb,
// sigma_t_scale 40), one thread, so the figures are per core.
//
//   BM_PhotonTrace          trace_photons() on 1 thread: real collisions/s (the full photon pass:
//                           light sampling, Embree floor hits, delta tracking, HG sampling, storing)
//   BM_FreeFlight           GridMedium::sample_free_flight() alone on rays from the spot light to
//                           random points of the medium's box: real collisions/s, lookups/s
//   BM_MediumWalk           the photon random walk inside the medium (delta tracking, albedo
//                           roulette, HG scattering; no surfaces, no storing) started by the spot
//                           light's rays: real collisions/s and density lookups (tentative)/s
//
// Rates are per CPU second of the (single) benchmark thread, so that other processes on a shared
// machine distort them less; the real time is printed as well.
//
// usage: bench_tracing [--benchmark_filter=...] [--benchmark_repetitions=N]
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include <filesystem>

#include "bench_common.h"
#include "core/henyey_greenstein.h"
#include "core/rng.h"
#include "core/sampling.h"
#include "photon/photon_tracer.h"
#include "scene/grid_medium.h"
#include "render/run_config.h"

using namespace vpm;

namespace {

const Scene& default_scene() {
    static const RunConfig config = RunConfig::load(bench::config_path("default.toml"));
    return *config.scene;
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
BENCHMARK(BM_PhotonTrace)->Arg(100000)->Unit(benchmark::kMillisecond);

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
BENCHMARK(BM_FreeFlight)->Unit(benchmark::kMillisecond);

void BM_MediumWalk(benchmark::State& state) {
    const Scene& scene = default_scene();
    const auto* medium = dynamic_cast<const GridMedium*>(scene.media.at(0).get());
    if (!medium) {
        state.SkipWithError("default scene has no grid medium");
        return;
    }
    const Vec3 origin(-1.6, 2.6, 1.2), target(0.0, 0.6, 0.0);   // the spot light and its aim
    const Vec3 axis = (target - origin).normalized();
    const Frame frame(axis);
    const double cos_max = std::cos(28.0 * kPi / 180.0);
    const double albedo = medium->albedo().maxCoeff(), g = medium->g();
    Rng rng(11, 0);
    TrackingStats st;
    int64_t real = 0, paths = 0;
    for (auto _ : state) {
        for (int i = 0; i < 4096; ++i, ++paths) {
            // uniform direction in the spot cone
            const double c = 1.0 - rng.uniform() * (1.0 - cos_max), phi = 2.0 * kPi * rng.uniform();
            const double sn = std::sqrt(std::max(0.0, 1.0 - c * c));
            Ray ray{origin, frame.to_world(Vec3(sn * std::cos(phi), sn * std::sin(phi), c)).normalized()};
            for (int bounce = 0; bounce < 1000; ++bounce) {
                const double t = medium->sample_free_flight(ray, kInfinity, rng, &st);
                if (!(t < kInfinity)) break;
                ++real;
                if (rng.uniform() >= albedo) break;
                const double u1 = rng.uniform(), u2 = rng.uniform();
                ray = Ray{ray.at(t), hg_sample(ray.dir, g, u1, u2)};
            }
        }
    }
    state.counters["collisions/s"] = benchmark::Counter(double(real), benchmark::Counter::kIsRate);
    state.counters["lookups/s"] = benchmark::Counter(double(st.lookups), benchmark::Counter::kIsRate);
    state.counters["lookups/collision"] = real ? double(st.lookups) / double(real) : 0.0;
    state.counters["collisions/path"] = double(real) / double(paths);
}
BENCHMARK(BM_MediumWalk)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
