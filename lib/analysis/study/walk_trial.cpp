#include "analysis/study/walk_trial.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/error.h"
#include "core/henyey_greenstein.h"
#include "core/math.h"
#include "core/sampling/sampling.h"
#include "photon/estimate/estimators.h"
#include "photon/estimate/walk_estimate.h"

namespace vpm {

std::string WalkMedium::label() const {
    char buf[64];
    std::snprintf(buf, sizeof buf, "walks/a%g/g%g", albedo, g);
    return buf;
}

const std::vector<WalkMedium>& study_walk_media() {
    static const std::vector<WalkMedium> media = {{0.3, 0.0}, {0.5, 0.0}, {0.9, 0.0}, {0.99, 0.0},
                                                  {0.3, 0.8}, {0.5, 0.8}, {0.9, 0.8}, {0.99, 0.8}};
    return media;
}

const std::vector<std::string>& walk_study_methods() {
    static const std::vector<std::string> names = {"classic", "corrected", "walk_classic", "walk_corrected",
                                                   "leave_group_out"};
    return names;
}

namespace {

// One walk from `start`: photons at the collisions, unwrapped.
void random_walk(const WalkMedium& m, const Vec3& start, Rng& rng, std::vector<Vec3>& out) {
    out.clear();
    Vec3 x = start;
    const double u1 = rng.uniform(), u2 = rng.uniform();
    Vec3 d = sample_uniform_sphere(u1, u2);   // the incoming direction of the first collision
    out.push_back(x);
    while (rng.uniform() < m.albedo) {
        const double v1 = rng.uniform(), v2 = rng.uniform();
        d = hg_sample(d, m.g, v1, v2);
        x += -std::log(1.0 - rng.uniform()) * d;
        out.push_back(x);
    }
}

struct Near {
    double d2;
    uint32_t walk;
    bool operator<(const Near& o) const { return d2 < o.d2 || (d2 == o.d2 && walk < o.walk); }
};

// The overlap fraction |B(0, R) and B(d, R)| / V(R) in 3D, u = d / R.
double ball_overlap(double u) { return u >= 2.0 ? 0.0 : 1.0 - 0.75 * u + u * u * u / 16.0; }

double poisson_pmf(size_t j, double m) { return std::exp(double(j) * std::log(m) - m - std::lgamma(double(j) + 1.0)); }

}  // namespace

void walk_trial(const WalkMedium& medium, const WalkTrialSettings& st, const std::vector<size_t>& ks, Rng& rng,
                std::vector<double>& out, size_t& photons) {
    const size_t nm = walk_study_methods().size(), kmax = ks.back();
    const double mean_photons = 1.0 / (1.0 - medium.albedo);
    const double side = std::cbrt(double(st.walks) * mean_photons / st.density);
    std::vector<Vec3> pos;
    std::vector<uint32_t> walk_of;
    std::vector<Vec3> walk;
    for (size_t w = 0; w < st.walks; ++w) {
        const Vec3 start(rng.uniform() * side, rng.uniform() * side, rng.uniform() * side);
        random_walk(medium, start, rng, walk);
        for (const Vec3& x : walk) {
            Vec3 y;
            for (int a = 0; a < 3; ++a) y[a] = x[a] - side * std::floor(x[a] / side);   // into the periodic cube
            pos.push_back(y);
            walk_of.push_back(uint32_t(w));
        }
    }
    photons = pos.size();
    out.assign(ks.size() * nm, 0.0);
    const double w_unit = 1.0 / st.density;   // unit power per photon over the truth: estimates read e directly
    std::vector<Near> all(pos.size());
    std::vector<double> w, d2;
    std::vector<uint32_t> slots;
    const Estimator classic = Estimator::named("classic"), corrected = Estimator::named("corrected");
    for (size_t q = 0; q < st.queries; ++q) {
        const Vec3 x(rng.uniform() * side, rng.uniform() * side, rng.uniform() * side);
        for (size_t i = 0; i < pos.size(); ++i) {
            double s = 0.0;
            for (int a = 0; a < 3; ++a) {
                double d = std::abs(pos[i][a] - x[a]);
                d = std::min(d, side - d);   // the nearest periodic image
                s += d * d;
            }
            all[i] = Near{s, walk_of[i]};
        }
        // The nearest M photons, M doubled until they hold k_max walks and k_max / 2 photons of
        // each walk half (leave_group_out).
        size_t m = std::min(all.size(), 4 * kmax);
        for (;;) {
            std::nth_element(all.begin(), all.begin() + long(m - 1), all.end());
            std::sort(all.begin(), all.begin() + long(m));
            size_t walks = 0, half[2] = {0, 0};
            walk_neighbourhood_size(m, kmax, [&](size_t i) { return all[i].walk; }, slots, walks);
            for (size_t i = 0; i < m; ++i) ++half[all[i].walk & 1u];
            if ((walks >= kmax && half[0] >= kmax && half[1] >= kmax) || m == all.size()) break;
            m = std::min(all.size(), 2 * m);
        }
        w.assign(m, w_unit);
        d2.resize(m);
        for (size_t i = 0; i < m; ++i) d2[i] = all[i].d2;
        const bool complete = m == all.size();
        auto walk_at = [&](size_t i) { return all[i].walk; };
        for (size_t ki = 0; ki < ks.size(); ++ki) {
            const size_t k = ks[ki];
            double* row = &out[ki * nm];
            row[0] += estimate_density<double>(classic, w.data(), d2.data(), m, complete, k, kInfinity, 3).value;
            row[1] += estimate_density<double>(corrected, w.data(), d2.data(), m, complete, k, kInfinity, 3).value;
            const Estimate<double> wc =
                estimate_density_walks<double>(classic, w.data(), d2.data(), m, walk_at, complete, k, kInfinity, 3, slots);
            if (2.0 * wc.radius >= side)
                throw Error("study: walks scenario: a walk ball of radius " + std::to_string(wc.radius) +
                            " reaches half the periodic cube's side " + std::to_string(side) + "; use more walks per trial");
            row[2] += wc.value;
            row[3] += estimate_density_walks<double>(corrected, w.data(), d2.data(), m, walk_at, complete, k, kInfinity, 3,
                                                     slots)
                          .value;
            // leave_group_out (group_estimate.h): each walk half counted within the other half's
            // ceil(k/2)-th photon, over its ball's volume.
            const size_t mh = (k + 1) / 2;
            double r2[2] = {-1.0, -1.0};   // r2[h]: the squared radius of half h's ball
            size_t count[2] = {0, 0};
            for (size_t i = 0; i < m && (r2[0] < 0.0 || r2[1] < 0.0); ++i) {
                const unsigned h = all[i].walk & 1u;
                if (++count[h] == mh) r2[1 - h] = d2[i];
            }
            if (r2[0] < 0.0 || r2[1] < 0.0) throw Error("study: walks scenario: too few photons for leave_group_out");
            for (unsigned h = 0; h < 2; ++h) {
                size_t inside = 0;
                for (size_t i = 0; i < m && d2[i] < r2[h]; ++i) inside += (all[i].walk & 1u) == h;
                row[4] += double(inside) * w_unit / ball_volume(3, std::sqrt(r2[h]));
            }
        }
    }
    for (double& v : out) v /= double(st.queries);
}

WalkClustering walk_clustering(const WalkMedium& medium, size_t walks, Rng& rng, double max_radius, Rng& point_rng,
                               size_t points) {
    // Ordered sibling pairs binned by distance (log bins; closer than the first edge: the first bin).
    const size_t bins = 2048;
    const double d_lo = 1e-4 * max_radius, d_hi = 2.0 * max_radius, step = std::log(d_hi / d_lo) / double(bins);
    std::vector<double> hist(bins, 0.0);
    const size_t radii = 256;
    const double r_lo = 1e-3 * max_radius;
    std::vector<double> radius(radii);
    for (size_t i = 0; i < radii; ++i) radius[i] = r_lo * std::pow(max_radius / r_lo, double(i) / double(radii - 1));
    // The volume within r of a walk, int 1[D(x) < r] dx with D(x) its nearest photon's distance, by
    // importance sampling: x = y_i + rho u, photon i uniform, rho log-uniform in [r_lo, max_radius],
    // u uniform in the unit ball. Its density is q(x) = mean_i g(|x - y_i|), g(d) = the mixture of
    // ball densities 1 / V(rho) over rho > max(d, r_lo); weight 1 / q counted at every grid radius
    // above D(x) (unbiased for r <= max_radius, where q > 0 wherever D < r).
    const double log_span = std::log(max_radius / r_lo);
    auto g = [&](double d) {
        const double a = std::max(d, r_lo);
        return a >= max_radius ? 0.0 : (1.0 / (a * a * a) - 1.0 / (max_radius * max_radius * max_radius)) / (4.0 * kPi * log_span);
    };
    std::vector<double> entered(radii, 0.0);   // sum of the weights first counted at each grid radius
    std::vector<Vec3> walk;
    double photons = 0.0;
    for (size_t w = 0; w < walks; ++w) {
        random_walk(medium, Vec3::Zero(), rng, walk);
        photons += double(walk.size());
        for (size_t p = 0; p < points; ++p) {
            const size_t i = std::min(walk.size() - 1, size_t(point_rng.uniform() * double(walk.size())));
            const double rho = r_lo * std::exp(point_rng.uniform() * log_span);
            const double u1 = point_rng.uniform(), u2 = point_rng.uniform(), u3 = point_rng.uniform();
            const Vec3 x = walk[i] + rho * sample_uniform_ball(u1, u2, u3);
            double nearest = kInfinity, q = 0.0;
            for (const Vec3& y : walk) {
                const double d = (x - y).norm();
                nearest = std::min(nearest, d);
                q += g(d);
            }
            q /= double(walk.size());
            const size_t first = size_t(std::upper_bound(radius.begin(), radius.end(), nearest) - radius.begin());
            if (first < radii) entered[first] += 1.0 / (q * double(points));
        }
        for (size_t i = 0; i < walk.size(); ++i)
            for (size_t j = i + 1; j < walk.size(); ++j) {
                const double d = (walk[i] - walk[j]).norm();
                if (d >= d_hi) continue;
                const double b = d <= d_lo ? 0.0 : std::floor(std::log(d / d_lo) / step);
                hist[std::min(bins - 1, size_t(b))] += 2.0;
            }
    }
    WalkClustering c;
    c.photons_per_walk = photons / double(walks);
    c.radius = radius;
    double union_volume = 0.0;   // summed over the walks
    for (size_t i = 0; i < radii; ++i) {
        const double r = radius[i];
        double s = 0.0;
        for (size_t b = 0; b < bins; ++b)
            if (hist[b] > 0.0) s += hist[b] * ball_overlap(d_lo * std::exp((double(b) + 0.5) * step) / r);
        c.s.push_back(s / photons);
        union_volume += entered[i];
        c.c.push_back(union_volume > 0.0 ? photons * ball_volume(3, r) / union_volume : 1.0);
    }
    return c;
}

namespace {

// s at expected count m (ball volume m / density), linear in log r between the grid's radii; below
// the grid's first radius (1e-3 of the largest) s ~ r^3 is negligible: taken as 0 there; beyond its
// last radius the caller's grid was too small: an error, not a clamp.
double siblings(double m, double density, const WalkClustering& c) {
    const double r = std::cbrt(3.0 * m / (4.0 * kPi * density));
    if (r <= c.radius.front()) return 0.0;
    if (r > c.radius.back())
        throw Error("study: walks theory: radius " + std::to_string(r) + " beyond the clustering grid (" +
                    std::to_string(c.radius.back()) + ")");
    const size_t j = size_t(std::upper_bound(c.radius.begin(), c.radius.end(), r) - c.radius.begin());
    if (j >= c.radius.size()) return c.s.back();
    const double t = std::log(r / c.radius[j - 1]) / std::log(c.radius[j] / c.radius[j - 1]);
    return c.s[j - 1] + t * (c.s[j] - c.s[j - 1]);
}

// c at expected count m, linear in log r between the grid's radii (1 below the grid: a ball far
// below the photon spacing holds one photon of the walk that enters it); beyond the grid an error.
double entering_photons(double m, double density, const WalkClustering& c) {
    const double r = std::cbrt(3.0 * m / (4.0 * kPi * density));
    if (r <= c.radius.front()) return 1.0;
    if (r > c.radius.back())
        throw Error("study: walks theory: radius " + std::to_string(r) + " beyond the clustering grid (" +
                    std::to_string(c.radius.back()) + ")");
    const size_t j = size_t(std::upper_bound(c.radius.begin(), c.radius.end(), r) - c.radius.begin());
    if (j >= c.radius.size()) return c.c.back();
    const double t = std::log(r / c.radius[j - 1]) / std::log(c.radius[j] / c.radius[j - 1]);
    return c.c[j - 1] + t * (c.c[j] - c.c[j - 1]);
}

// P(Poisson(mu) >= k) = 1 - sum_{j < k} p_j(mu).
double poisson_at_least(size_t k, double mu) {
    double below = 0.0;
    for (size_t j = 0; j < k; ++j) below += poisson_pmf(j, mu);
    return std::max(0.0, 1.0 - below);
}

// Walk classic: E[S_k] / rho - 1 = E[1 / V(R)] / lambda = int_0^inf P(H(m) >= k) dm / m^2, H(m) ~
// Poisson(m / c(m)) the walks entering a ball of m expected photons (docs/walk_correlation.md).
// Integrated in log m up to the m where the probability is 1 to 1e-12, then the tail 1 / m.
double walk_classic_error(size_t k, double density, const WalkClustering& c) {
    const double kd = double(k), m_lo = 1e-6;
    const double h = 1e-3;   // log m step
    double sum = 0.0, m = m_lo;
    for (;;) {
        const double p = poisson_at_least(k, m / entering_photons(m, density, c));
        if (p > 1.0 - 1e-12 && m > kd) return sum + 0.5 * h * p / m + 1.0 / m;
        sum += (m == m_lo ? 0.5 : 1.0) * h * p / m;
        m *= std::exp(h);
    }
}

// int_0^inf s(m)/2 f(m) dm / m over the Poisson support of k, in log m.
template <class F>
double poisson_integral(size_t k, double density, const WalkClustering& c, const F& f) {
    const double m_lo = 1e-6, m_hi = double(k) + 12.0 * std::sqrt(double(k)) + 30.0;
    const size_t steps = 4000;
    const double h = std::log(m_hi / m_lo) / double(steps);
    double sum = 0.0;
    for (size_t i = 0; i <= steps; ++i) {
        const double m = m_lo * std::exp(double(i) * h);
        const double v = 0.5 * siblings(m, density, c) * f(m);
        sum += (i == 0 || i == steps ? 0.5 : 1.0) * v;
    }
    return sum * h;
}

}  // namespace

double walk_theory_error(size_t method, size_t k, double density, const WalkClustering& c) {
    const double kd = double(k);
    auto corrected_bias = [&] {
        return (kd - 1.0) * poisson_integral(k, density, c, [k](double m) { return poisson_pmf(k - 2, m) - poisson_pmf(k - 1, m); });
    };
    switch (method) {
        case 0: return kd / (kd - 1.0) * (1.0 + corrected_bias()) - 1.0;
        case 1: return corrected_bias();
        case 2: return walk_classic_error(k, density, c);
        case 3:
        case 4: return 0.0;
        default: throw Error("walk_theory_error: method index " + std::to_string(method) + " out of range");
    }
}

double walk_siblings_at(size_t k, double density, const WalkClustering& c) { return siblings(double(k), density, c); }

double walk_entering_photons_at(size_t k, double density, const WalkClustering& c) {
    return entering_photons(double(k), density, c);
}

}  // namespace vpm
