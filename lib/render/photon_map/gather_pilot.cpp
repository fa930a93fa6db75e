// photons.gather = "pilot": a pilot per pass renders 8 x 8 camera rays spread over the image, 16
// samples each on streams of their own, with each candidate gather (collision, march, threshold) and
// keeps the one with the least variance x cost, the cost from deterministic counts (kNN queries, rays,
// ball-quadrature lookups): the same choice on any machine, thread count and scale. The variance is
// relative, each ray's weighted by 1 / (R^2 + eps) as the relMSE weighs its pixel (render/plan/relative_error.h;
// R: the ray's mean over every candidate's samples), so the brightest rays do not decide alone. A member of
// PhotonMapIntegrator kept apart from its passes; the automatic plan (auto_gather.cpp) supersedes it.
#include <vector>

#include <tbb/parallel_for.h>

#include "core/sampling/rng.h"
#include "render/photon_map/photon_map_integrator.h"
#include "render/plan/relative_error.h"
#include "scene/media/homogeneous_medium.h"

namespace vpm {

void PhotonMapIntegrator::choose_gather(const PassContext& context) {
    // Work units per counted operation, in nanoseconds of single-thread work (fitted to bench_photon_map
    // and the photon tracer's benchmarks, BENCHMARKS.md): a kNN query 700 + 280 k, a tracked segment 1000
    // in grids (about one real collision of delta tracking plus the DDA) and 100 in homogeneous media
    // (closed forms), a sigma_t lookup of the ball quadrature 50. Only their ratios matter, and only
    // between candidates whose variance x cost differ by less than the error of these weights.
    bool grids = false;
    for (const auto& m : scene_.media) grids = grids || !dynamic_cast<const HomogeneousMedium*>(m.get());
    const double w_query = 700.0 + 280.0 * double(pass_.k), w_ray = grids ? 1000.0 : 100.0, w_lookup = 50.0;
    constexpr int kSide = 8, kSamples = 16;
    constexpr int kRays = kSide * kSide;
    const GatherMode candidates[] = {GatherMode::collision, GatherMode::march, GatherMode::threshold};
    GatherPilotStats pilot = choice_.pilot ? *choice_.pilot : GatherPilotStats{};
    pilot.candidates = {"collision", "march", "auto"};
    pilot.variance.assign(3, 0.0);
    pilot.cost.assign(3, 0.0);

    // Each candidate's work is counted apart from the run's, on counters of its own.
    const Camera& camera = scene_.camera;
    const uint64_t seed = mix64(context.seed ^ 0x70696c6f74ULL);   // streams apart from the camera pass's
    std::vector<std::vector<double>> variance(3, std::vector<double>(kRays)), mean(3, std::vector<double>(kRays));
    int chosen = 0;
    for (int c = 0; c < 3; ++c) {
        const PassMaps maps = pass_maps(pass_, candidates[c], *maps_.volume, maps_.surface, decision_.view(), maps_.volume_regions,
                                        maps_.surface ? maps_.surface_regions : nullptr);
        const CameraPath path(scene_, settings_, maps, both_strategies_);
        CounterSet counters;
        tbb::parallel_for(0, kRays, [&](int j) {
            Rng rng(seed, context.stream_offset * uint64_t(kRays) + uint64_t(j));
            double mean_j = 0.0, m2 = 0.0;
            for (int s = 0; s < kSamples; ++s) {
                const double x = (j % kSide + rng.uniform()) / kSide * camera.width();
                const double y = (j / kSide + rng.uniform()) / kSide * camera.height();
                const Rgb l = path.trace(camera.generate_ray(x, y), 0, rng, counters.local());
                const double v = all_finite(l) ? 0.2126 * l[0] + 0.7152 * l[1] + 0.0722 * l[2] : 0.0;
                const double d = v - mean_j;
                mean_j += d / (s + 1);
                m2 += d * (v - mean_j);
            }
            variance[size_t(c)][size_t(j)] = m2 / (kSamples - 1);
            mean[size_t(c)][size_t(j)] = mean_j;
        });
        const CameraTotals t = sum_counters(counters);
        const uint64_t queries = t.estimates.stats.queries + t.surface_stats.queries, rays = t.rays,
                       lookups = t.estimates.lookups;
        pilot.cost[size_t(c)] = (w_query * double(queries) + w_ray * double(rays) + w_lookup * double(lookups)) / (kRays * kSamples);
    }
    for (int j = 0; j < kRays; ++j) {
        const double weight = relative_error_weight((mean[0][size_t(j)] + mean[1][size_t(j)] + mean[2][size_t(j)]) / 3.0);
        for (int c = 0; c < 3; ++c) pilot.variance[size_t(c)] += weight * variance[size_t(c)][size_t(j)] / kRays;
    }
    // Least variance x cost; with no variance anywhere (nothing lit in view), least cost.
    for (int c = 1; c < 3; ++c) {
        const double a = pilot.variance[size_t(c)] * pilot.cost[size_t(c)];
        const double b = pilot.variance[size_t(chosen)] * pilot.cost[size_t(chosen)];
        if (a < b || (a == b && pilot.cost[size_t(c)] < pilot.cost[size_t(chosen)])) chosen = c;
    }
    choice_.gather = candidates[chosen];
    pilot.chosen = pilot.candidates[size_t(chosen)];
    pilot.chosen_count.resize(3, 0);
    ++pilot.chosen_count[size_t(chosen)];
    choice_.pilot = pilot;
    if (context.log && context.first_of_run) {
        *context.log << "gather: the pilot chose \"" << pilot.chosen << "\" (pilot, " << kRays << " rays x " << kSamples
                     << " samples: relative variance x cost";
        for (int c = 0; c < 3; ++c)
            *context.log << (c ? ", " : " ") << pilot.candidates[size_t(c)] << " " << pilot.variance[size_t(c)] * pilot.cost[size_t(c)];
        *context.log << ")\n";
    }
}

}  // namespace vpm
