#include "analysis/study/sample_point_trial.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/sampling/sampling.h"

namespace vpm {

namespace {

// Minimal-image offset on the unit torus.
double wrap(double d) { return d - std::round(d); }

}  // namespace

void sample_point_trial(size_t n, double length, const std::vector<size_t>& ks, const std::vector<Kernel>& kernels,
                        Rng& rng, double* point, double* beam) {
    std::vector<Vec3> p(n);
    for (Vec3& x : p) x = Vec3(rng.uniform(), rng.uniform(), rng.uniform());
    const Vec3 centre(0.5, 0.5, 0.5);
    const Vec3 dir = sample_uniform_sphere(rng.uniform(), rng.uniform());
    const Vec3 origin = centre - 0.5 * length * dir;
    const size_t kmax = ks.back(), nk = ks.size(), nkern = kernels.size();
    const double rho = double(n);
    std::fill(point, point + nk * nkern, 0.0);
    std::fill(beam, beam + nk * nkern, 0.0);
    std::vector<double> d2(n - 1);
    for (size_t i = 0; i < n; ++i) {
        // Squared distances to the other points, the kmax smallest in order.
        size_t m = 0;
        for (size_t j = 0; j < n; ++j)
            if (j != i) {
                const Vec3 d(wrap(p[j].x() - p[i].x()), wrap(p[j].y() - p[i].y()), wrap(p[j].z() - p[i].z()));
                d2[m++] = d.squaredNorm();
            }
        std::nth_element(d2.begin(), d2.begin() + long(kmax - 1), d2.end());
        std::sort(d2.begin(), d2.begin() + long(kmax));
        if (!(d2[kmax - 1] < 0.25))   // the minimal image would be wrong: refuse rather than bias
            throw Error("study: beam scenario: a k = " + std::to_string(kmax) + " radius reached half the unit torus (n = " +
                        std::to_string(n) + "); raise --n");
        // Point estimate at the centre: the minimal image (radii < 1/2).
        const Vec3 c(wrap(p[i].x() - 0.5), wrap(p[i].y() - 0.5), wrap(p[i].z() - 0.5));
        const double dc2 = c.squaredNorm();
        for (size_t ki = 0; ki < nk; ++ki) {
            const double r2 = d2[ks[ki] - 1], r = std::sqrt(r2);
            if (dc2 < r2)
                for (size_t kk = 0; kk < nkern; ++kk)
                    point[ki * nkern + kk] += kernels[kk].weight(dc2 / r2, 3) / (4.0 / 3.0 * kPi * r2 * r * rho);
            // Beam: every periodic image of the point whose foot lies on the segment inside its disc.
            for (int a = -1; a <= 1; ++a)
                for (int b = -1; b <= 1; ++b)
                    for (int e = -1; e <= 1; ++e) {
                        const Vec3 v = p[i] + Vec3(a, b, e) - origin;
                        const double t = v.dot(dir);
                        if (t < 0.0 || t > length) continue;
                        const double dd2 = std::max(0.0, v.squaredNorm() - t * t);
                        if (!(dd2 < r2)) continue;
                        for (size_t kk = 0; kk < nkern; ++kk)
                            beam[ki * nkern + kk] += kernels[kk].weight(dd2 / r2, 2) / (kPi * r2 * rho * length);
                    }
        }
    }
}

// variance_factor() is the mean of K^2 over the mean of K squared; an unnormalised kernel's mean
// M_d / n_d enters squared.
double sample_point_variance_3d(const Kernel& kernel, size_t k) {
    const double m = sample_point_mean(kernel, 3);
    return m * m * kernel.moments(3).variance_factor() / (double(k) - 1.0);
}

double sample_point_variance_beam(const Kernel& kernel, size_t k, double rho, double length) {
    const double inv_r2 = std::pow(4.0 * kPi * rho / 3.0, 2.0 / 3.0) * std::exp(std::lgamma(double(k) - 2.0 / 3.0) - std::lgamma(double(k)));
    const double m = sample_point_mean(kernel, 2);
    return m * m * kernel.moments(2).variance_factor() * inv_r2 / (kPi * rho * length);
}

double sample_point_mean(const Kernel& kernel, int dim) { return kernel.profile_mean(dim) / kernel.normalisation(dim); }

}  // namespace vpm
