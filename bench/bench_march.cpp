// The march's per-segment work in a grid (issue 20 items 3-4): the optical-depth profile of a
// camera segment and the march's point placement on it, one thread, CPU time of the thread.
// Medium: media/blob.vdb as the scene matrix's blob cells place it (scale 4/3 about the origin,
// sigma_t_scale 1.505 = optical thickness 1 across), rays from the cells' camera (0, 0, 4)
// through random points of the blob's bounds (about half of them cross its mass).
//
//   BM_MarchProfile          GridMedium::optical_depth_profile over the whole ray
//   BM_MarchPoints/N/C       place_counted_march_points with N = photons.gather_queries and
//                            C = 0 fixed, 1 mass (the default), 2 free_flight: the profile and
//                            its inversions, what the march pays per crossed segment
//
// usage: bench_march [--benchmark_filter=...] [--benchmark_repetitions=N]
#include <benchmark/benchmark.h>

#include <vector>

#include "bench_common.h"
#include "core/sampling/rng.h"
#include "io/vdb_io.h"
#include "scene/media/grid_medium.h"
#include "transport/march_points.h"

using namespace vpm;

namespace {

const GridMedium& blob() {
    static const GridMedium m = [] {
        Eigen::Affine3d xf = Eigen::Affine3d::Identity();
        xf.scale(4.0 / 3.0);
        return GridMedium(load_vdb_density(bench::config_path("../media/blob.vdb")), 1.5053289237876728, Rgb::Constant(0.9),
                          0.0, xf);
    }();
    return m;
}

std::vector<Ray> camera_rays(const GridMedium& m) {
    const Vec3 origin(0.0, 0.0, 4.0);
    const Bounds3 b = m.bounds();
    Rng rng(22, 0);
    std::vector<Ray> rays(4096);
    for (auto& r : rays) {
        const Vec3 target(b.lo.x() + rng.uniform() * (b.hi.x() - b.lo.x()), b.lo.y() + rng.uniform() * (b.hi.y() - b.lo.y()),
                          b.lo.z() + rng.uniform() * (b.hi.z() - b.lo.z()));
        r = Ray{origin, (target - origin).normalized()};
    }
    return rays;
}

void BM_MarchProfile(benchmark::State& state) {
    const GridMedium& m = blob();
    const std::vector<Ray> rays = camera_rays(m);
    OpticalDepthProfile profile;
    double depth = 0.0;
    int64_t pieces = 0, n = 0;
    for (auto _ : state) {
        for (const Ray& r : rays) {
            m.optical_depth_profile(r, kInfinity, profile);
            depth += profile.total();
            pieces += int64_t(profile.size());
        }
        n += int64_t(rays.size());
    }
    benchmark::DoNotOptimize(depth);
    state.counters["rays/s"] = benchmark::Counter(double(n), benchmark::Counter::kIsRate);
    state.counters["pieces/ray"] = double(pieces) / double(n);
}
BENCHMARK(BM_MarchProfile)->Unit(benchmark::kMillisecond);

void BM_MarchPoints(benchmark::State& state) {
    const GridMedium& m = blob();
    const std::vector<Ray> rays = camera_rays(m);
    const int gather_queries = int(state.range(0));
    const MarchCount count = state.range(1) == 0 ? MarchCount::fixed : state.range(1) == 1 ? MarchCount::mass : MarchCount::free_flight;
    OpticalDepthProfile profile;
    std::vector<double> ts;
    Rng rng(22, 1);
    double sum = 0.0;
    int64_t points = 0, n = 0;
    for (auto _ : state) {
        for (const Ray& r : rays) {
            const MarchMass mass = place_counted_march_points(m, r, kInfinity, gather_queries, count, rng, profile, ts);
            sum += mass.mass;
            points += int64_t(ts.size());
        }
        n += int64_t(rays.size());
    }
    benchmark::DoNotOptimize(sum);
    state.counters["rays/s"] = benchmark::Counter(double(n), benchmark::Counter::kIsRate);
    state.counters["points/ray"] = double(points) / double(n);
}
BENCHMARK(BM_MarchPoints)->Args({4, 0})->Args({4, 1})->Args({4, 2})->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
