#include "analysis/study/photon_beam_trial.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/math.h"
#include "core/sampling/sampling.h"
#include "photon/map/photon_beam_bvh.h"

namespace vpm {

namespace {

constexpr double kHalfBox = 1.5;           // the cube of beam centres
constexpr double kQueryLength = 1.0;
constexpr double kMaxWidth = 0.5;          // crossings with u below stay inside the cube
constexpr double kMeanCrossing = 410.0;    // mean crossings with u < kMaxWidth
// Crossings with u < r: rho * 2 r * s * L * E[sin] with E[sin] = pi / 4 for isotropic directions.
constexpr double kRho = kMeanCrossing / (2.0 * kMaxWidth * kQueryLength * 1.0 * (kPi / 4.0));

// A Poisson count of the given mean (exponential gaps: exact, ~mean draws).
size_t poisson(double mean, Rng& rng) {
    size_t n = 0;
    double s = -std::log1p(-rng.uniform());
    while (s < mean) {
        ++n;
        s += -std::log1p(-rng.uniform());
    }
    return n;
}

}  // namespace

void photon_beam_trial(const std::vector<size_t>& ks, const std::vector<Kernel>& kernels, Rng& rng, double* out) {
    const double side = 2.0 * kHalfBox;
    const size_t n = poisson(kRho * side * side * side, rng);
    const Vec3 o(0.0, 0.0, -0.5 * kQueryLength), d = Vec3::UnitZ();
    struct Hit {
        double u, sin_theta;
    };
    std::vector<Hit> hits;
    for (size_t i = 0; i < n; ++i) {
        const Vec3 c(side * (rng.uniform() - 0.5), side * (rng.uniform() - 0.5), side * (rng.uniform() - 0.5));
        const Vec3 w = sample_uniform_sphere(rng.uniform(), rng.uniform());
        BeamCrossing x;
        if (photon_beam_crossing(o, d, kQueryLength, c - 0.5 * w, w, 1.0, x)) hits.push_back({x.u, x.sin_theta});
    }
    std::sort(hits.begin(), hits.end(), [](const Hit& a, const Hit& b) { return a.u < b.u; });
    const double truth = kRho * kQueryLength;
    const size_t nk = kernels.size();
    for (size_t ki = 0; ki < ks.size(); ++ki) {
        const size_t k = ks[ki];
        for (size_t kk = 0; kk < nk; ++kk) {
            double* slot = out + (ki * nk + kk) * 2;
            if (hits.size() < k || hits[k - 1].u >= kMaxWidth) {   // never at the scenario's density (see the header)
                slot[0] = slot[1] = std::numeric_limits<double>::quiet_NaN();
                continue;
            }
            const double r = hits[k - 1].u;
            double inner = 0.0;
            for (size_t i = 0; i + 1 < k; ++i)
                inner += kernels[kk].weight(hits[i].u * hits[i].u / (r * r), 1) / hits[i].sin_theta;
            const double kth = kernels[kk].weight(1.0, 1) / hits[k - 1].sin_theta;
            slot[0] = (inner + kth) / (2.0 * r) / truth;
            slot[1] = inner / (2.0 * r) / truth;
        }
    }
}

BeamBalloonTheory photon_beam_balloon_theory(const Kernel& kernel, size_t k, bool keep_kth, double d) {
    const KernelMoments& m = kernel.moments(1);
    const double m1 = m.m1, m2 = m.m2, k1 = m.k1, km1 = double(k) - 1.0, km2 = double(k) - 2.0;
    BeamBalloonTheory th;
    if (!keep_kth) {
        th.mean = m1;
        th.variance = k > 2 ? d * m2 / km2 : kInfinity;
        return th;
    }
    th.mean = m1 + k1 / km1;
    if (k <= 2) {
        th.variance = kInfinity;
        return th;
    }
    const double s2 = (km1 * d * m2 + km1 * km2 * m1 * m1 + 2.0 * km1 * m1 * k1 + d * k1 * k1) / (km1 * km2);
    th.variance = s2 - th.mean * th.mean;
    return th;
}

}  // namespace vpm
