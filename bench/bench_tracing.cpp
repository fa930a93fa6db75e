// Photon tracing through the default VDB medium (configs/default.toml: media/plume.vdb,
// sigma_t_scale 40), one thread, so the figures are per core.
//
//   BM_PhotonTrace          trace_photons() on 1 thread: real collisions/s (the full photon pass:
//                           light sampling, Embree floor hits, delta tracking, HG sampling, storing)
//   BM_FreeFlight           GridMedium::sample_free_flight() alone on rays from the spot light to
//                           random points of the medium's box: real collisions/s, lookups/s
//   BM_MediumWalk/T/S       the photon random walk inside the medium (free flights, albedo
//                           roulette, HG scattering; no surfaces, no storing) started by the spot
//                           light's rays, at sigma_t_scale S (40 = the default scene): real
//                           collisions/s and, per real collision, tentative collisions of delta
//                           tracking, density lookups (the tentative collisions that survive
//                           thinning by the sub-block majorants), voxel cells integrated in
//                           closed form, lookups + cells ("evals": each reads one 8-voxel
//                           stencil) and majorant-walk DDA steps. T = 0: the current
//                           tracker (lib/scene/media/majorant_tracking.h); T = 1: the tracker before
//                           issue 12 (delta tracking against the 8^3-block majorants only), kept
//                           here as the baseline so before/after run interleaved in one process.
//   BM_DensityLookup/M      DensityGrid::density on the plume: M = 0 random points of the box,
//                           M = 1 quarter-voxel steps along rays (ns per lookup = 1e9 / rate)
//
// Rates are per CPU second of the (single) benchmark thread, so that other processes on a shared
// machine distort them less; the real time is printed as well.
//
// usage: bench_tracing [--benchmark_filter=...] [--benchmark_repetitions=N]
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include <cmath>
#include <filesystem>
#include <vector>

#include "bench_common.h"
#include "core/henyey_greenstein.h"
#include "core/sampling/rng.h"
#include "core/sampling/sampling.h"
#include "photon/trace/photon_tracer.h"
#include "scene/media/grid_medium.h"
#include "render/run/run_config.h"

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
    state.counters["cells/collision"] = real ? double(st.cells) / double(real) : 0.0;
    state.counters["steps/ray"] = double(st.blocks) / double(n);
}
BENCHMARK(BM_FreeFlight)->Unit(benchmark::kMillisecond);

// The tracker before issue 12: delta tracking against the per-block majorants (8^3 blocks with a
// one-voxel ring), the exponential restarted at each block. Baseline for BM_MediumWalk only.
double legacy_free_flight(const GridMedium& m, const Ray& ray, double tmax, Rng& rng, TrackingStats& st) {
    const Vec3 o = m.world_to_index() * ray.origin;
    const Vec3 d = m.world_to_index().linear() * ray.dir;
    const double scale = m.sigma_t_scale();
    const DensityGrid& grid = m.grid();
    double result = kInfinity;
    st.blocks += grid.traverse(o, d, 0.0, tmax, [&](double ta, double tb, float majorant) {
        if (!(majorant > 0.0f)) return true;
        const double mu = scale * majorant;
        for (double t = ta;;) {
            const double tn = t - std::log1p(-rng.uniform()) / mu;
            t = tn > t ? tn : std::nextafter(t, kInfinity);
            if (!(t < tb)) return true;
            ++st.lookups;
            if (rng.uniform() * mu >= scale * grid.density(o + t * d)) continue;
            result = t;
            return false;
        }
    });
    return result;
}

void BM_MediumWalk(benchmark::State& state) {
    const Scene& scene = default_scene();
    const auto* base = dynamic_cast<const GridMedium*>(scene.media.at(0).get());
    if (!base) {
        state.SkipWithError("default scene has no grid medium");
        return;
    }
    const bool legacy = state.range(0) == 1;
    const double scale = double(state.range(1));
    const GridMedium medium(base->grid(), scale, base->albedo(), base->g());   // index_to_world is in the grid
    const Vec3 origin(-1.6, 2.6, 1.2), target(0.0, 0.6, 0.0);   // the spot light and its aim
    const Vec3 axis = (target - origin).normalized();
    const Frame frame(axis);
    const double cos_max = std::cos(28.0 * kPi / 180.0);
    const double albedo = medium.albedo().maxCoeff(), g = medium.g();
    // Paths per iteration: 4096 in the default medium; fewer where each path makes thousands of
    // collisions (albedo 0.92: ~12 per path that enters), so that one iteration stays short.
    const int paths_per_iter = scale > 1000 ? 256 : 4096;
    Rng rng(11, 0);
    TrackingStats st;
    int64_t real = 0, paths = 0;
    for (auto _ : state) {
        for (int i = 0; i < paths_per_iter; ++i, ++paths) {
            // uniform direction in the spot cone
            const double c = 1.0 - rng.uniform() * (1.0 - cos_max), phi = 2.0 * kPi * rng.uniform();
            const double sn = std::sqrt(std::max(0.0, 1.0 - c * c));
            Ray ray{origin, frame.to_world(Vec3(sn * std::cos(phi), sn * std::sin(phi), c)).normalized()};
            for (int bounce = 0; bounce < 1000; ++bounce) {
                const double t = legacy ? legacy_free_flight(medium, ray, kInfinity, rng, st)
                                        : medium.sample_free_flight(ray, kInfinity, rng, &st);
                if (!(t < kInfinity)) break;
                ++real;
                if (rng.uniform() >= albedo) break;
                const double u1 = rng.uniform(), u2 = rng.uniform();
                ray = Ray{ray.at(t), hg_sample(ray.dir, g, u1, u2)};
            }
        }
    }
    const double r = real ? double(real) : 1.0;
    state.counters["collisions/s"] = benchmark::Counter(double(real), benchmark::Counter::kIsRate);
    state.counters["tentative/collision"] = double(legacy ? st.lookups : st.tentative) / r;
    state.counters["lookups/collision"] = double(st.lookups) / r;
    state.counters["cells/collision"] = double(st.cells) / r;
    state.counters["evals/collision"] = double(st.lookups + st.cells) / r;
    state.counters["steps/collision"] = double(st.blocks) / r;
    state.counters["collisions/path"] = double(real) / double(paths);
}
// Default density (40) both trackers, then the dense cells of the stress matrix (issue 12); the
// legacy tracker only where it finishes in reasonable time.
BENCHMARK(BM_MediumWalk)
    ->ArgNames({"legacy", "scale"})
    ->Args({0, 40})
    ->Args({1, 40})
    ->Args({0, 400})
    ->Args({1, 400})
    ->Args({0, 10000})
    ->Args({1, 10000})
    ->Args({0, 1000000})
    ->Args({0, 100000000})
    ->Unit(benchmark::kMillisecond);

void BM_DensityLookup(benchmark::State& state) {
    const Scene& scene = default_scene();
    const auto* medium = dynamic_cast<const GridMedium*>(scene.media.at(0).get());
    if (!medium) {
        state.SkipWithError("default scene has no grid medium");
        return;
    }
    const DensityGrid& g = medium->grid();
    const Bounds3 ib = g.index_bounds();
    Rng rng(42);
    constexpr int kPoints = 4096;
    std::vector<Vec3> pts;
    pts.reserve(kPoints);
    if (state.range(0) == 0) {
        for (int i = 0; i < kPoints; ++i)
            pts.emplace_back(ib.lo.x() + rng.uniform() * (ib.hi.x() - ib.lo.x()), ib.lo.y() + rng.uniform() * (ib.hi.y() - ib.lo.y()),
                             ib.lo.z() + rng.uniform() * (ib.hi.z() - ib.lo.z()));
    } else {
        while (int(pts.size()) < kPoints) {   // quarter-voxel steps along rays through the volume
            const Vec3 o(ib.lo.x(), ib.lo.y() + rng.uniform() * (ib.hi.y() - ib.lo.y()), ib.lo.z() + rng.uniform() * (ib.hi.z() - ib.lo.z()));
            const Vec3 d = Vec3(1, 0.3 * (rng.uniform() - 0.5), 0.3 * (rng.uniform() - 0.5)).normalized() * 0.25;
            for (int s = 0; s < 256 && int(pts.size()) < kPoints; ++s) pts.push_back(o + s * d);
        }
    }
    double sink = 0.0;
    for (auto _ : state) {
        for (const Vec3& p : pts) sink += g.density(p);
        benchmark::DoNotOptimize(sink);
    }
    state.counters["lookups/s"] = benchmark::Counter(double(kPoints) * double(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_DensityLookup)->ArgName("along_ray")->Arg(0)->Arg(1);

}  // namespace

BENCHMARK_MAIN();
