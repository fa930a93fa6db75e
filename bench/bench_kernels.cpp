// Time cost of the kernel evaluation (issue 15): the density estimate with each kernel, on its
// own (pre-gathered neighbour lists) and with the kNN gather it follows in the renderer
// (estimate_in_scattering: gather + Henyey-Greenstein weights + estimator), per query.
// Single thread, CPU time of this thread, one process for every variant (fair under load).
//
//   ./build/bench_kernels [photons = 1e6] [queries = 20000]
#include <time.h>

#include <cstdio>
#include <cstdlib>
#include <vector>

#include "core/sampling/rng.h"
#include "core/sampling/sampling.h"
#include "photon/estimate/estimators.h"
#include "photon/map/photon_map.h"

using namespace vpm;

namespace {

double cpu_seconds() {
    timespec t;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

}  // namespace

int main(int argc, char** argv) {
    const size_t n = argc > 1 ? size_t(std::atof(argv[1])) : 1000000;
    const size_t nq = argc > 2 ? size_t(std::atof(argv[2])) : 20000;
    Rng rng(2014, 15);
    std::vector<PhotonInput> ph(n);
    for (auto& p : ph) {
        p.position = Vec3(rng.uniform(), rng.uniform(), rng.uniform());
        const double u1 = rng.uniform(), u2 = rng.uniform();
        p.direction = sample_uniform_sphere(u1, u2);
        p.power = Rgb::Constant(1.0 / double(n));
    }
    const PhotonMap map(ph);
    std::vector<Vec3> queries(nq);
    for (auto& q : queries) q = Vec3(0.1 + 0.8 * rng.uniform(), 0.1 + 0.8 * rng.uniform(), 0.1 + 0.8 * rng.uniform());
    std::vector<Kernel> kernels = Kernel::all();
    kernels.push_back(Kernel::named("cone", 0.5));
    std::printf("photons %zu, queries %zu, single thread, CPU time per query (ns)\n", n, nq);
    std::printf("| k | kernel | estimate only (ns) | gather + estimate (ns) | kNN gather alone (ns) | kernel share of gather + estimate |\n"
                "|---:|---|---:|---:|---:|---:|\n");
    for (size_t k : {8, 32, 128}) {
        // pre-gathered lists for the estimator-only timing
        const size_t m = std::min<size_t>(nq, 2000);
        std::vector<std::vector<Rgb>> w(m);
        std::vector<std::vector<double>> d2(m);
        NeighbourList list;
        for (size_t q = 0; q < m; ++q) {
            const size_t found = map.knn(queries[q], k, kInfinity, list);
            for (size_t i = 0; i < found; ++i) {
                w[q].push_back(list[i].power);
                d2[q].push_back(list[i].d2);
            }
        }
        double t0 = cpu_seconds();
        for (const Vec3& x : queries) map.knn(x, k, kInfinity, list);
        const double gather = (cpu_seconds() - t0) / double(nq);
        for (const Kernel& kern : kernels) {
            const Estimator e = Estimator::named("corrected").with_kernel(kern);
            const int reps = int(200000 / m);
            double sink = 0;
            t0 = cpu_seconds();
            for (int r = 0; r < reps; ++r)
                for (size_t q = 0; q < m; ++q)
                    sink += estimate_density<Rgb>(e, w[q].data(), d2[q].data(), w[q].size(), false, k, kInfinity, 3)
                                .value[1];
            const double est = (cpu_seconds() - t0) / double(reps * m);
            GatherBuffers buf;
            t0 = cpu_seconds();
            for (const Vec3& x : queries)
                sink += estimate_in_scattering(map, x, Vec3::UnitZ(), 0.4, e, k, kInfinity, buf).value[1];
            const double full = (cpu_seconds() - t0) / double(nq);
            std::printf("| %zu | %s | %.0f | %.0f | %.0f | %.1f%% |%s\n", k, kern.label().c_str(), est * 1e9, full * 1e9,
                        gather * 1e9, 100.0 * est / full, sink == 12345.0 ? " " : "");
        }
    }
    return 0;
}
