// Issue 56 item 4 (docs/walk_correlation.md section 6): the renderer's half-space bias split by depth
// into walk clustering and the smoothing of a ball of random radius. Not a Google Benchmark: one
// table per run.
//
// The half-space of bench/halfspace_bias.sh (albedo 0.5, sigma_t 1, box [-10,10]x[-10,0]x[-10,10],
// a directional light straight down, photons.count photons a map, photons.extinction = "linear").
// Every map is traced by vpm's own photon pass (stream offset = map index; the camera where the bench's
// is, since the directional light aims nested shares of its photons at what the camera sees,
// scene/lights/emission_bounds.h: the photon count under the camera, and so r_k, depend on it), and every estimate is
// vpm's VolumeEstimator with the scene's BallExtinction, at query points under the middle of the lit
// face (a 5 x 5 lateral grid in [-2, 2]^2) at depths z_j = (j + 1/2) dz. On the same maps:
//
//   photons   the tracer's photons, photon-neighbour corrected (k)  (the renderer's default)
//   walks     the tracer's photons, walk-neighbour corrected (k)
//   moved     the photons of the middle 16 x 16 of the face, each moved to a uniform lateral place
//             in it, depth kept, each its own walk: independent points with the middle's depth
//             profile; photon-neighbour corrected (k)
//   fixed     the tracer's photons, every photon within r0 (the estimator's rule (a))
//   fixed_m   the moved photons within r0
//   F(r), C(r)  on the moved photons: the fixed-radius estimate and the photon count in a ball of
//             radius r, for r on a grid (the prediction below)
//   W(r)      on the tracer's photons: the number of walks with a photon within r (the walk form's
//             prediction: the same mixture with walks as the units)
//   truth     the power density of the photons in depth bins of width dz centred on z_j (truth_mid:
//             the middle 16 x 16 of the face, every estimate's truth; truth_all: the whole face), over
//             4 pi: an estimate of the incident radiance without any ball
//
// For independent points (a Poisson process of mean density lambda), given r_k the k - 1 inner photons
// are i.i.d. over the ball, so E[corrected | r_k] = (k - 1) F(r_k) / Lambda(r_k), F(r) the fixed-radius
// mean, Lambda(r) the ball's mean count; Lambda(r_k) ~ Gamma(k, 1), and (k - 1) gamma_k(t) / t =
// gamma_{k-1}(t), hence
//     E[corrected] = E[ F(Lambda^-1(T)) ],  T ~ Gamma(k - 1, 1),
// the fixed-radius mean at a random radius whose ball holds a Gamma(k - 1) count. The columns pred
// and moved compare it with the measurement (bench/halfspace_split.py forms it from F and C).
//
//   rk_photons, rk_moved  the mean r_k of the tracer's photons and of the moved ones
//
//   bench_halfspace_split [--maps 400] [--k 32] [--r0 0.9] [--count 8000] [--depths 60] [--dz 0.1] [--dump FILE]
// prints CSV: one row per depth with every quantity's mean over maps and its standard error (W in the
// dump only), then one row "camera" with the camera's integral sum_j albedo exp(-z_j) dz of each (per
// map, then mean). --dump writes every map's values for bench/halfspace_split.py.
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <string>
#include <vector>

#include "core/sampling/rng.h"
#include "photon/estimate/ball_extinction.h"
#include "photon/map/photon_map.h"
#include "render/photon_map/photon_map_integrator.h"
#include "render/photon_map/photon_pass.h"
#include "render/photon_map/volume_estimate.h"
#include "render/run/run_config.h"
#include "render/run/run_stats.h"

using namespace vpm;

namespace {

constexpr double kAlbedo = 0.5;
constexpr double kHalfWidth = 10.0;
constexpr double kMiddle = 8.0;   // the middle of the face: |x|, |z| < 8, 2 mfp from the side faces

// Mean and standard error over independent maps.
struct Moments {
    double s = 0.0, s2 = 0.0;
    size_t n = 0;
    void add(double v) {
        s += v;
        s2 += v * v;
        ++n;
    }
    double mean() const { return n ? s / double(n) : 0.0; }
    double se() const {
        if (n < 2) return 0.0;
        const double m = mean();
        return std::sqrt(std::max(0.0, (s2 / double(n) - m * m) / double(n - 1)));
    }
};

double arg(int argc, char** argv, const char* name, double fallback) {
    for (int i = 1; i + 1 < argc; ++i)
        if (std::strcmp(argv[i], name) == 0) return std::atof(argv[i + 1]);
    return fallback;
}

std::vector<PhotonInput> inputs_of(const PhotonMap& map) {
    std::vector<PhotonInput> out(map.size());
    for (size_t i = 0; i < map.size(); ++i) {
        out[i].position = map.position(i);
        out[i].direction = map.direction(i);
        out[i].power = map.power(i);
        out[i].walk = map.walk(i);
        out[i].group = uint8_t(map.walk(i) % kWalkGroups);
    }
    return out;
}

}  // namespace

int main(int argc, char** argv) {
    const int maps = int(arg(argc, argv, "--maps", 400));
    const size_t k = size_t(arg(argc, argv, "--k", 32));
    const double r0 = arg(argc, argv, "--r0", 0.9);
    const int count = int(arg(argc, argv, "--count", 8000));
    const int depths = int(arg(argc, argv, "--depths", 60));
    const double dz = arg(argc, argv, "--dz", 0.1);
    // --dump FILE: every map's per-depth values as CSV (map, depth, the columns, F and C), for paired
    // differences (bench/halfspace_split.py).
    std::FILE* dump = nullptr;
    for (int i = 1; i + 1 < argc; ++i)
        if (std::strcmp(argv[i], "--dump") == 0) dump = std::fopen(argv[i + 1], "w");
    const RunConfig config = RunConfig::load(
        VPM_SOURCE_DIR "/configs/semi_infinite.toml",
        {"media.0.albedo=0.5", "media.0.min=[-10, -10, -10]", "media.0.max=[10, 0, 10]", "camera.position=[0, 200, 0]",
         "render.integrator=photon_map",
         "photons.gather=collision", "photons.direct=photon_map", "photons.count=" + std::to_string(count),
         "photons.k=" + std::to_string(k), "render.threads=1"});
    const PhotonMapSettings& settings = photon_map_settings(config);
    const BallExtinction ball(config.scene->media);
    std::vector<double> radii;
    for (double r = 0.2; r <= 1.6 + 1e-9; r += 0.05) radii.push_back(r);
    const size_t nr = radii.size();
    if (dump) {
        std::fprintf(dump, "map,depth,photons,walks,moved,fixed,fixed_m,truth_mid,truth_all,rk_moved,rk_photons");
        for (double r : radii) std::fprintf(dump, ",F%.2f,C%.2f,W%.2f", r, r, r);
        std::fprintf(dump, "\n");
    }

    enum Column { photons, walks, moved, fixed, fixed_m, truth_mid, truth_all, rk_moved, rk_photons, kColumns };
    const char* names[kColumns] = {"photons", "walks", "moved", "fixed", "fixed_m", "truth_mid", "truth_all", "rk_moved", "rk_photons"};
    const size_t nd = static_cast<size_t>(depths);
    std::vector<std::array<Moments, kColumns>> by_depth(nd);
    std::vector<std::vector<Moments>> F(nd, std::vector<Moments>(nr)), C(nd, std::vector<Moments>(nr));
    std::array<Moments, kColumns> camera;
    std::vector<Moments> cameraF(nr);
    Moments stored;

    std::optional<LightAllocation> allocation;
    EstimateScratch scratch;
    std::vector<uint64_t> stamp;   // per walk id: the query that last met it
    uint64_t stamp_id = 0;
    EstimateCounts counts;
    const Vec3 w_o(0.0, 1.0, 0.0);
    for (int m = 0; m < maps; ++m) {
        PassContext context;
        context.seed = config.render.seed;
        context.stream_offset = uint64_t(m);
        context.run_stream_offset = 0;
        context.progress = false;
        RunStats stats;
        PhotonMaps traced = run_photon_pass(*config.scene, settings, context, false, stats, allocation);
        const PhotonMap& real = traced.volume;
        stored.add(double(real.size()));
        std::vector<PhotonInput> in = inputs_of(real);
        // The truth: power density in depth bins centred on the query depths (channel 0, grey light).
        std::vector<double> mid(nd, 0.0), all(nd, 0.0);
        Rng rng(56, uint64_t(m));
        for (size_t i = 0; i < in.size(); ++i) {
            const Vec3& p = in[i].position;
            const int bin = int(std::floor(-p.y() / dz));
            if (bin >= 0 && bin < depths) {
                all[size_t(bin)] += in[i].power[0];
                if (std::abs(p.x()) < kMiddle && std::abs(p.z()) < kMiddle) mid[size_t(bin)] += in[i].power[0];
            }
        }
        // The photons of the middle 16 x 16, each moved to a uniform place in it: the middle's depth
        // profile (truth_mid, shared with the tracer's photons), independent points.
        std::vector<PhotonInput> middle;
        for (const PhotonInput& p : in)
            if (std::abs(p.position.x()) < kMiddle && std::abs(p.position.z()) < kMiddle) {
                PhotonInput q = p;
                q.position.x() = (2.0 * rng.uniform() - 1.0) * kMiddle;
                q.position.z() = (2.0 * rng.uniform() - 1.0) * kMiddle;
                q.walk = middle.size();
                q.group = uint8_t(q.walk % kWalkGroups);
                middle.push_back(q);
            }
        const PhotonMap shuffled(middle);
        auto estimator_for = [&](const PhotonMap& map, size_t kk, double max_radius, Neighbourhood hood) {
            return VolumeEstimator{map, DecisionMap{}, kk, settings.estimator, max_radius, 0.0,
                                   ExtinctionNormalisation::linear, false, ball, hood};
        };
        const VolumeEstimator e_photons = estimator_for(real, k, kInfinity, Neighbourhood::photons);
        const VolumeEstimator e_walks = estimator_for(real, k, kInfinity, Neighbourhood::walks);
        const VolumeEstimator e_moved = estimator_for(shuffled, k, kInfinity, Neighbourhood::photons);
        const VolumeEstimator e_fixed = estimator_for(real, real.size(), r0, Neighbourhood::photons);
        const VolumeEstimator e_fixed_m = estimator_for(shuffled, shuffled.size(), r0, Neighbourhood::photons);
        std::array<double, kColumns> cam{};
        std::vector<double> camF(nr, 0.0);
        for (int j = 0; j < depths; ++j) {
            const double z = (j + 0.5) * dz;
            std::array<double, kColumns> v{};
            std::vector<double> f(nr, 0.0), c(nr, 0.0), walks_in(nr, 0.0);
            int q = 0;
            for (int a = 0; a < 5; ++a)
                for (int b = 0; b < 5; ++b, ++q) {
                    const Vec3 x(-2.0 + a, -z, -2.0 + b);
                    auto value = [&](const VolumeEstimator& e) { return e.estimate(x, w_o, 0.0, 1.0, scratch, counts).incident[0]; };
                    v[photons] += value(e_photons);
                    v[rk_photons] += std::sqrt(scratch.buffers.list[k - 1].d2);
                    v[walks] += value(e_walks);
                    v[moved] += value(e_moved);
                    v[rk_moved] += std::sqrt(scratch.buffers.list[k - 1].d2);   // the list: the k nearest, sorted
                    v[fixed] += value(e_fixed);
                    v[fixed_m] += value(e_fixed_m);
                    for (size_t i = 0; i < nr; ++i) {
                        const VolumeEstimator e = estimator_for(shuffled, shuffled.size(), radii[i], Neighbourhood::photons);
                        f[i] += value(e);
                        c[i] += double(scratch.buffers.list.size());   // every photon within radii[i]
                    }
                    // The walks of the tracer's photons first met within each radius (the walk form's
                    // Lambda_w(R), section 2 of docs/walk_correlation.md).
                    ++stamp_id;
                    real.knn(x, real.size(), radii.back(), scratch.buffers.list);
                    for (size_t n = 0; n < scratch.buffers.list.size(); ++n) {
                        const uint32_t walk = real.walk(scratch.buffers.list[n].index);
                        if (walk >= stamp.size()) stamp.resize(size_t(walk) + 1, 0);
                        if (stamp[walk] == stamp_id) continue;
                        stamp[walk] = stamp_id;
                        const double d = std::sqrt(scratch.buffers.list[n].d2);
                        for (size_t i = 0; i < nr; ++i)
                            if (d <= radii[i]) walks_in[i] += 1.0;
                    }
                }
            for (double& x : v) x /= q;
            v[truth_mid] = mid[size_t(j)] / (4.0 * kMiddle * kMiddle * dz) / (4.0 * kPi);
            v[truth_all] = all[size_t(j)] / (4.0 * kHalfWidth * kHalfWidth * dz) / (4.0 * kPi);
            const double w = kAlbedo * std::exp(-z) * dz;
            for (int col = 0; col < kColumns; ++col) {
                by_depth[size_t(j)][size_t(col)].add(v[size_t(col)]);
                cam[size_t(col)] += w * v[size_t(col)];
            }
            if (dump) {
                std::fprintf(dump, "%d,%.4f", m, z);
                for (double x : v) std::fprintf(dump, ",%.9g", x);
                for (size_t i = 0; i < nr; ++i) std::fprintf(dump, ",%.9g,%.6g,%.6g", f[i] / q, c[i] / q, walks_in[i] / q);
                std::fprintf(dump, "\n");
            }
            for (size_t i = 0; i < nr; ++i) {
                F[size_t(j)][i].add(f[i] / q);
                C[size_t(j)][i].add(c[i] / q);
                camF[i] += w * f[i] / q;
            }
        }
        for (int col = 0; col < kColumns; ++col) camera[size_t(col)].add(cam[size_t(col)]);
        for (size_t i = 0; i < nr; ++i) cameraF[i].add(camF[i]);
        if ((m + 1) % 50 == 0) std::fprintf(stderr, "map %d\n", m + 1);
    }
    std::printf("# maps %d, k %zu, r0 %g, photons.count %d, stored per map %.1f, linear fallbacks %llu\n", maps, k, r0,
                count, stored.mean(), static_cast<unsigned long long>(counts.linear_fallbacks));
    std::printf("depth");
    for (int col = 0; col < kColumns; ++col) std::printf(",%s,%s_se", names[col], names[col]);
    for (size_t i = 0; i < nr; ++i) std::printf(",F%.2f,F%.2f_se,C%.2f", radii[i], radii[i], radii[i]);
    std::printf("\n");
    auto row = [&](const char* label, const std::array<Moments, kColumns>& r, const std::vector<Moments>& f,
                   const std::vector<Moments>* c) {
        std::printf("%s", label);
        for (int col = 0; col < kColumns; ++col) std::printf(",%.9g,%.3g", r[size_t(col)].mean(), r[size_t(col)].se());
        for (size_t i = 0; i < nr; ++i)
            std::printf(",%.9g,%.3g,%.9g", f[i].mean(), f[i].se(), c ? (*c)[i].mean() : 0.0);
        std::printf("\n");
    };
    for (int j = 0; j < depths; ++j) {
        char label[32];
        std::snprintf(label, sizeof label, "%.4f", (j + 0.5) * dz);
        row(label, by_depth[size_t(j)], F[size_t(j)], &C[size_t(j)]);
    }
    row("camera", camera, cameraF, nullptr);
    if (dump) std::fclose(dump);
    return 0;
}
