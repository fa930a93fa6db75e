// Sample-point (beam) estimates on a uniform cloud: measured mean and relative variance against
// the first-order (Campbell) theory of docs/beam_estimate.md, for k = 2..256, point (3D) and beam
// (2D disc, segment of length 0.4) estimates, constant and Epanechnikov kernels, beside the balloon
// corrected estimate's relative variance 1/(k-2). Prints a markdown table (a plain main: it is a
// study, not a speed benchmark).
//
//   build/bench_sample_point [trials=400] [n=20000]
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "core/sampling/rng.h"
#include "core/sampling/sampling.h"
#include "photon/map/photon_radii.h"
#include "photon/estimate/sample_point_estimate.h"

using namespace vpm;

int main(int argc, char** argv) {
    const int trials = argc > 1 ? std::atoi(argv[1]) : 400;
    const size_t n = argc > 2 ? size_t(std::atoll(argv[2])) : 20000;
    const double rho = double(n) / (4.0 / 3.0 * kPi), length = 0.4;
    const std::vector<size_t> ks = {2, 4, 8, 16, 32, 64, 128, 256};
    const std::vector<Kernel> kernels = {Kernel::constant(), Kernel::named("epanechnikov")};
    struct Acc {
        double s = 0, s2 = 0;
        int n = 0;
    };
    std::vector<Acc> acc(ks.size() * kernels.size() * 2);
    for (int t = 0; t < trials; ++t) {
        Rng rng(91, uint64_t(t));
        std::vector<PhotonInput> photons(n);
        for (PhotonInput& p : photons) {
            p.position = sample_uniform_ball(rng.uniform(), rng.uniform(), rng.uniform());
            p.power = Rgb::Ones();
        }
        const PhotonMap map(photons);
        const Vec3 dir = sample_uniform_sphere(rng.uniform(), rng.uniform());
        // Radii only for photons that can reach the segment (within 0.2 + 2 r_k of the centre; the
        // same search photon_radii does for every photon, restricted to save time).
        NeighbourList list;
        for (size_t ki = 0; ki < ks.size(); ++ki) {
            const double reach = 0.5 * length + 2.0 * std::cbrt(double(ks[ki]) / rho / (4.0 / 3.0 * kPi));
            std::vector<SamplePoint> near;
            for (size_t i = 0; i < map.size(); ++i) {
                if (map.position(i).norm() > reach) continue;
                map.knn(map.position(i), ks[ki] + 1, kInfinity, list);
                if (map.position(i).norm() < 0.5 * length + list.max_distance())
                    near.push_back({map.position(i), list.max_distance(), 1.0});
            }
            for (size_t kk = 0; kk < kernels.size(); ++kk) {
                const double v[2] = {sample_point_density(Vec3::Zero(), near, kernels[kk]) / rho,
                                     beam_line_density(-0.5 * length * dir, dir, length, near, kernels[kk]) / (rho * length)};
                for (int e = 0; e < 2; ++e) {
                    Acc& a = acc[(ki * kernels.size() + kk) * 2 + size_t(e)];
                    a.s += v[e], a.s2 += v[e] * v[e], ++a.n;
                }
            }
        }
        if ((t + 1) % 50 == 0) std::fprintf(stderr, "%d / %d trials\n", t + 1, trials);
    }
    std::printf("n = %zu points in the unit ball, %d clouds; relative variance: measured (first-order theory)\n\n", n, trials);
    std::printf("| kernel | k | point mean | point rel. var | beam mean | beam rel. var | balloon corrected rel. var 1/(k-2) |\n");
    std::printf("|---|---|---|---|---|---|---|\n");
    for (size_t kk = 0; kk < kernels.size(); ++kk)
        for (size_t ki = 0; ki < ks.size(); ++ki) {
            const double k = double(ks[ki]);
            // q_d: the mean over the unit ball / disc of (K / n_d)^2 (1 for the constant kernel).
            const double q3 = kernels[kk].moments(3).variance_factor(), q2 = kernels[kk].moments(2).variance_factor();
            const double th_point = q3 / (k - 1.0);
            const double th_beam = q2 * std::pow(4.0 * kPi * rho / 3.0, 2.0 / 3.0) * std::exp(std::lgamma(k - 2.0 / 3.0) - std::lgamma(k)) /
                                   (kPi * rho * length);
            const Acc& p = acc[(ki * kernels.size() + kk) * 2];
            const Acc& b = acc[(ki * kernels.size() + kk) * 2 + 1];
            auto mean = [](const Acc& a) { return a.s / a.n; };
            auto var = [&](const Acc& a) { return a.s2 / a.n - mean(a) * mean(a); };
            std::printf("| %s | %zu | %.4f +- %.4f | %.4f (%.4f) | %.4f +- %.4f | %.5f (%.5f) | %s |\n", kernels[kk].label().c_str(),
                        ks[ki], mean(p), std::sqrt(var(p) / p.n), var(p), th_point, mean(b), std::sqrt(var(b) / b.n), var(b),
                        th_beam, k > 2 ? std::to_string(1.0 / (k - 2.0)).substr(0, 6).c_str() : "inf");
        }
    return 0;
}
