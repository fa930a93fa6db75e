#include "analysis/study/knn_smoothing.h"

#include <array>
#include <cmath>

#include "core/error.h"
#include "core/math.h"

namespace vpm {

namespace {

constexpr int kNodes = 64;

struct GaussLegendre {
    std::array<double, kNodes> x{}, w{};   // on [-1, 1]
    GaussLegendre() {
        for (int i = 0; i < kNodes; ++i) {
            double t = std::cos(kPi * (i + 0.75) / (kNodes + 0.5));   // Newton from the usual guess
            for (int it = 0; it < 100; ++it) {
                double p0 = 1.0, p1 = t;
                for (int n = 2; n <= kNodes; ++n) {
                    const double p2 = ((2 * n - 1) * t * p1 - (n - 1) * p0) / n;
                    p0 = p1;
                    p1 = p2;
                }
                const double dp = kNodes * (t * p1 - p0) / (t * t - 1.0);
                const double step = p1 / dp;
                t -= step;
                if (std::abs(step) < 1e-15) {
                    x[size_t(i)] = t;
                    w[size_t(i)] = 2.0 / ((1.0 - t * t) * dp * dp);
                    break;
                }
            }
        }
    }
};

const GaussLegendre& nodes() {
    static const GaussLegendre g;
    return g;
}

}  // namespace

ClippedBallMeans clipped_ball_means(const DepthDensity& density, double z, double r) {
    if (!(r > 0.0) || !(z >= 0.0)) throw Error("clipped_ball_means: needs r > 0 and z >= 0");
    const GaussLegendre& g = nodes();
    const double lo = std::max(-r, -z), half = 0.5 * (r - lo), mid = 0.5 * (r + lo);
    // Moments of the slice areas a(u) = pi (r^2 - u^2) (m0, centroid c, depth variance s), then the
    // density's: integral lambda a, integral lambda a h, integral lambda.
    double m0 = 0.0, m1 = 0.0, m2 = 0.0;
    for (int i = 0; i < kNodes; ++i) {
        const double u = mid + half * g.x[size_t(i)], a = kPi * (r * r - u * u) * half * g.w[size_t(i)];
        m0 += a;
        m1 += a * u;
        m2 += a * u * u;
    }
    const double c = m1 / m0, s = m2 / m0 - c * c;
    const bool offset = lo > -r;   // clipped: the centroid moves off x (unclipped, c is 0 and h is 1)
    ClippedBallMeans out;
    double weighted = 0.0, rate = 0.0;
    for (int i = 0; i < kNodes; ++i) {
        const double u = mid + half * g.x[size_t(i)], lam = density(z + u);
        const double a = kPi * (r * r - u * u) * half * g.w[size_t(i)];
        const double h = offset ? 1.0 - (u - c) * c / s : 1.0;
        out.mass += lam * a;
        weighted += lam * a * h;
        rate += lam * half * g.w[size_t(i)];
    }
    out.fixed_radius = weighted / m0;
    out.mass_rate = 2.0 * kPi * r * rate;   // the sphere's zone at depth z + u has area 2 pi r du
    return out;
}

double corrected_knn_mean(const DepthDensity& density, double z, size_t k, double max_radius, int steps) {
    if (k < 2) throw Error("corrected_knn_mean: needs k >= 2");
    if (steps < 2 || steps % 2) throw Error("corrected_knn_mean: steps must be even and >= 2");
    const double a = double(k) - 1.0;   // T ~ Gamma(a, 1)
    const double t_end = a + 14.0 * std::sqrt(a) + 40.0;   // beyond the 1 - 1e-12 quantile for every a >= 1
    double r_end = 0.05;
    while (r_end < max_radius && clipped_ball_means(density, z, r_end).mass < t_end) r_end = std::min(max_radius, 2.0 * r_end);
    const double log_norm = std::lgamma(a);
    auto integrand = [&](double r) {
        if (!(r > 0.0)) return 0.0;
        const ClippedBallMeans b = clipped_ball_means(density, z, r);
        if (!(b.mass > 0.0)) return 0.0;
        const double gamma_pdf = std::exp((a - 1.0) * std::log(b.mass) - b.mass - log_norm);
        return b.fixed_radius * gamma_pdf * b.mass_rate;
    };
    const double h = r_end / steps;
    double sum = integrand(0.0) + integrand(r_end);
    for (int i = 1; i < steps; ++i) sum += (i % 2 ? 4.0 : 2.0) * integrand(i * h);
    return sum * h / 3.0;
}

}  // namespace vpm
