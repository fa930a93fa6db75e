#include "render/map_noise_pilot.h"

#include <cmath>

#include <tbb/parallel_for.h>

#include "photon/walk_group_split.h"

namespace vpm {

namespace {

double luminance_of(const Rgb& l) { return all_finite(l) ? 0.2126 * l[0] + 0.7152 * l[1] + 0.0722 * l[2] : 0.0; }

// Per pixel: the mean of a's samples minus b's, squared, less the samples' share Var(a - b) / n.
double map_variance_of_difference(const std::vector<double>& a, const std::vector<double>& b) {
    constexpr int kPixels = kPilotSide * kPilotSide, n = kPilotSamples;
    double sum = 0.0;
    for (int j = 0; j < kPixels; ++j) {
        double mean = 0.0, m2 = 0.0;
        for (int s = 0; s < n; ++s) {
            const double d = a[size_t(j * n + s)] - b[size_t(j * n + s)];
            const double delta = d - mean;
            mean += delta / (s + 1);
            m2 += delta * (d - mean);
        }
        sum += mean * mean - m2 / (n - 1) / n;
    }
    return sum / kPixels;   // E[(mean_a - mean_b)^2] - Var(a - b) / n = V_map(a) + V_map(b)
}

// Per pixel: the mean over samples of (a + b) / 2 - f, squared, less its samples' share.
double squared_mean_difference(const std::vector<double>& a, const std::vector<double>& b, const std::vector<double>& f) {
    constexpr int kPixels = kPilotSide * kPilotSide, n = kPilotSamples;
    double sum = 0.0;
    for (int j = 0; j < kPixels; ++j) {
        double mean = 0.0, m2 = 0.0;
        for (int s = 0; s < n; ++s) {
            const size_t i = size_t(j * n + s);
            const double d = 0.5 * (a[i] + b[i]) - f[i];
            const double delta = d - mean;
            mean += delta / (s + 1);
            m2 += delta * (d - mean);
        }
        sum += mean * mean - m2 / (n - 1) / n;
    }
    return sum / kPixels;
}

}  // namespace

std::vector<GatherMeasurement> measure_gathers(const Camera& camera, const PhotonMap& map,
                                               const std::vector<std::string>& names,
                                               MapNoisePilotHooks& hooks, uint64_t seed, uint64_t stream) {
    constexpr int kPixels = kPilotSide * kPilotSide, n = kPilotSamples;
    const std::vector<PhotonMap> halves = split_by_walk_group(map, 2);
    const std::vector<const PhotonMap*> maps = {&map, &halves[0], &halves[1]};
    const int width = camera.width(), height = camera.height();
    std::vector<GatherMeasurement> out;
    for (size_t c = 0; c < names.size(); ++c) {
        std::vector<std::vector<double>> values(maps.size(), std::vector<double>(size_t(kPixels * n)));
        double cost = 0.0;
        CountedOperations ops;
        for (size_t m = 0; m < maps.size(); ++m) {
            hooks.use(int(c), maps[m]);
            const CountedOperations before = hooks.counts();
            tbb::parallel_for(0, kPixels, [&](int j) {
                const int px = std::min(width - 1, int((j % kPilotSide + 0.5) / kPilotSide * width));
                const int py = std::min(height - 1, int((j / kPilotSide + 0.5) / kPilotSide * height));
                for (int s = 0; s < n; ++s) {
                    // The same numbers for every map and candidate: the differences are the maps'.
                    Rng rng(seed, stream * uint64_t(kPixels * n) + uint64_t(j * n + s));
                    const double jx = rng.uniform(), jy = rng.uniform();
                    values[m][size_t(j * n + s)] = luminance_of(hooks.trace(camera.generate_ray(px + jx, py + jy), rng));
                }
            });
            if (m == 0) {
                const CountedOperations after = hooks.counts();
                const double samples = double(kPixels * n);
                ops = {(after.queries - before.queries) / samples, (after.rays - before.rays) / samples,
                       (after.lookups - before.lookups) / samples};
                cost = hooks.work(ops);
            }
        }
        GatherMeasurement g;
        g.name = names[c];
        g.sample_cost = cost;
        g.per_sample = ops;
        g.max_weight = hooks.counts().march_weight_max;   // over this candidate's traces (and the earlier ones')
        double v = 0.0;
        for (int j = 0; j < kPixels; ++j) {
            double mean = 0.0, m2 = 0.0;
            for (int s = 0; s < n; ++s) {
                const double x = values[0][size_t(j * n + s)], delta = x - mean;
                mean += delta / (s + 1);
                m2 += delta * (x - mean);
            }
            v += m2 / (n - 1);
        }
        g.v_camera = v / kPixels;
        double sum = 0.0;
        for (double x : values[0]) sum += x;
        g.mean = sum / double(values[0].size());
        // Pixels differ in mean, so the SE comes from the spread of the pixel means (each of n samples).
        double spread = 0.0;
        for (int j = 0; j < kPixels; ++j) {
            double pm = 0.0;
            for (int s = 0; s < n; ++s) pm += values[0][size_t(j * n + s)] / n;
            spread += (pm - g.mean) * (pm - g.mean);
        }
        g.mean_se = std::sqrt(spread / (kPixels - 1) / kPixels);
        g.v_map_half = 0.5 * map_variance_of_difference(values[1], values[2]);
        g.v_map_quarter = -1.0;
        // The half maps' balls are 2^(1/3) wider: with a bias ~ r^2 (a smooth density, the corrected
        // estimate's leading term) their mean is off by (2^(2/3) - 1) times the full map's bias.
        const double f = std::pow(2.0, 2.0 / 3.0) - 1.0;
        g.bias2 = squared_mean_difference(values[1], values[2], values[0]) / (f * f);
        out.push_back(g);
    }
    return out;
}

}  // namespace vpm
