// The photon-beam BVH's k-nearest query (photon/map/photon_beam_bvh.h) in a furnace-like field of
// short beams: random walks (sigma_t 0.6, albedo 1, isotropic) entering a sphere of radius 6 from
// its surface, every free flight a beam clipped to the sphere; queries from the centre to the
// sphere in uniform directions (6-unit segments, as the camera rays of configs/uniform_furnace.toml).
// Arguments: the pieces' length as a multiple of PhotonBeamBvh::automatic_piece_length (0: whole
// beams, one item each) and k. Counters: crossing tests per query, items per beam, bytes per beam,
// build seconds. The answers are the same for every piece length (tests/photon/map/photon_beam_bvh_test.cpp).
//
//   build/bench_photon_beam_bvh [--benchmark_filter=...]
#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>

#include "core/sampling/rng.h"
#include "core/sampling/sampling.h"
#include "photon/map/photon_beam_bvh.h"

using namespace vpm;

namespace {

constexpr double kRadius = 6.0, kSigma = 0.6;
constexpr size_t kPaths = 40000;

double sphere_exit(const Vec3& p, const Vec3& w) {
    const double b = p.dot(w), c = p.squaredNorm() - kRadius * kRadius;
    return -b + std::sqrt(std::max(b * b - c, 0.0));
}

const std::vector<PhotonBeam>& furnace_beams() {
    static const std::vector<PhotonBeam> beams = [] {
        std::vector<PhotonBeam> out;
        Rng rng(43, 1);
        for (size_t i = 0; i < kPaths; ++i) {
            const Vec3 n = sample_uniform_sphere(rng.uniform(), rng.uniform());
            Vec3 p = kRadius * (1.0 - 1e-12) * n;
            // Cosine-weighted inward, as the flux of a constant sky through the surface.
            const double u1 = rng.uniform(), phi = 2.0 * kPi * rng.uniform();
            const double cos_t = std::sqrt(1.0 - u1), sin_t = std::sqrt(u1);
            const Frame f(-n);
            Vec3 w = (sin_t * std::cos(phi)) * f.s + (sin_t * std::sin(phi)) * f.t + cos_t * f.n;
            for (int bounce = 0; bounce < 1000; ++bounce) {
                const double flight = -std::log1p(-rng.uniform()) / kSigma, exit = sphere_exit(p, w);
                out.push_back({p, w, std::min(flight, exit), Rgb::Ones()});
                if (flight >= exit) break;
                p += flight * w;
                w = sample_uniform_sphere(rng.uniform(), rng.uniform());
            }
        }
        return out;
    }();
    return beams;
}

void BM_BeamNearest(benchmark::State& state) {
    const std::vector<PhotonBeam>& beams = furnace_beams();
    const double scale = double(state.range(0)) / 4.0;
    const size_t k = size_t(state.range(1));
    const double piece = scale * PhotonBeamBvh::automatic_piece_length(beams);
    const auto start = std::chrono::steady_clock::now();
    const PhotonBeamBvh bvh(beams, {}, piece);
    const double build = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    Rng rng(44, 1);
    std::vector<BeamCrossing> near;
    uint64_t tested = 0, queries = 0;
    for (auto _ : state) {
        const Vec3 d = sample_uniform_sphere(rng.uniform(), rng.uniform());
        bvh.nearest(Vec3::Zero(), d, kRadius, k, kInfinity, near, UINT32_MAX, &tested);
        benchmark::DoNotOptimize(near.data());
        ++queries;
    }
    state.counters["tested/query"] = double(tested) / double(queries);
    state.counters["items/beam"] = double(bvh.item_count()) / double(bvh.size());
    state.counters["bytes/beam"] = double(bvh.memory_bytes()) / double(bvh.size());
    state.counters["build_s"] = build;
    state.counters["piece"] = piece;
}

// The sample-point form's width query: a beam's own segment against the others (skip itself).
void BM_BeamOwnNearest(benchmark::State& state) {
    const std::vector<PhotonBeam>& beams = furnace_beams();
    const double piece = double(state.range(0)) / 4.0 * PhotonBeamBvh::automatic_piece_length(beams);
    const size_t k = size_t(state.range(1));
    const PhotonBeamBvh bvh(beams, {}, piece);
    Rng rng(45, 1);
    std::vector<BeamCrossing> near;
    uint64_t tested = 0, queries = 0;
    for (auto _ : state) {
        const uint32_t j = uint32_t(rng.uniform() * double(beams.size()));
        const PhotonBeam& b = beams[j];
        bvh.nearest(b.origin, b.dir, b.length, k, kInfinity, near, j, &tested);
        benchmark::DoNotOptimize(near.data());
        ++queries;
    }
    state.counters["tested/query"] = double(tested) / double(queries);
}

}  // namespace

BENCHMARK(BM_BeamOwnNearest)->ArgsProduct({{0, 4}, {4}})->Unit(benchmark::kMicrosecond);
// Piece length in quarters of the automatic one (0: whole beams), k.
BENCHMARK(BM_BeamNearest)
    ->ArgsProduct({{0, 1, 2, 4, 8, 16}, {4, 32}})
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_MAIN();
