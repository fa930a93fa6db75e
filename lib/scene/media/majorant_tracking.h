#pragma once
// Free-flight sampling and transmittance over a majorant walk, shared by every medium that can
// give a density lookup and majorants along a ray (docs/design.md: "a medium gives density and
// majorants; tracking over them is shared code"). GridMedium uses it with the trilinear field of
// a DensityGrid; a procedural medium needs one Field type in one file.
//
// A Field describes one ray (the medium's own parametrisation, t in world units):
//
//   using Segment = ...;   // has members ta, tb (double) and majorant (double, density units)
//   template <class V> int walk(double t0, double t1, V&& visit) const;
//       calls visit(const Segment&) -> bool for consecutive pieces of [t0, t1] in order of t,
//       each with majorant >= the density everywhere on it (pieces with majorant 0 may be left
//       out); stops when visit returns false; returns the walk's step count (for statistics).
//   double density(const Segment& s, double t) const;   // density at t, t in [s.ta, s.tb]
//   double local_majorant(const Segment& s, double t) const;
//       a bound on density(s, t) at this t, <= s.majorant and cheaper than density() (e.g. a finer
//       level of majorants); may simply return s.majorant
//   struct Span { double majorant, t_end; ... };
//   void local_span(const Segment& s, double t, Span& out) const;   // (in place: a returned
//       struct written field by field and read back whole stalled store forwarding)
//       a finer cell around t: a bound on the density over the ray's piece [t, t_end] in it
//       (t <= t_end <= s.tb; may be {s.majorant, s.tb}); delta tracking runs at that rate there
//   double density_local(const Segment& s, const Span& sp, double t) const;
//       density at t, for t in [t, sp.t_end] of local_span (<= sp.majorant exactly)
//   static constexpr bool kHasExact;
//   and, when kHasExact (a closed-form optical depth is available on some segments):
//   double exact_cost(const Segment& s) const;
//       work of the closed form on s in units of density lookups (kInfinity: none on s)
//   double exact_depth(const Segment& s, TrackingStats& st) const;
//       integral of the density over [s.ta, s.tb] (world length x density)
//   double exact_sample(const Segment& s, double scale, double& E, TrackingStats& st) const;
//       the t in (s.ta, s.tb) where scale * integral_{s.ta}^{t} density = E, or kInfinity after
//       E -= scale * integral over the whole segment
//
// sigma_t = scale * density. Per segment the trackers pick, from the geometry alone (so every
// choice is deterministic and the estimator stays exact):
// - the closed form when scale * majorant * length (the expected number of tentative
//   collisions of delta tracking) exceeds its cost: free flights by inversion of the optical
//   depth, transmittance exp(-tau), no null collisions at all; this is what keeps the cost per
//   path bounded as the density grows;
// - otherwise delta tracking (free flights) or ratio tracking (transmittance) against the
//   segment's majorant, whose tentative collisions are first thinned by the local majorant:
//   a density lookup happens only at the points of the finer majorant process (mu_loc / mu of
//   them), so lookups follow the finer majorant while the walk steps only over segments. Free
//   flights go further: after a tentative collision, the rest of that finer cell (local_span)
//   runs at the cell's own rate, so tentative collisions follow the finer majorant too.
// Both are exact, and mixing them along a ray is too: the free flight carries one exponential
// optical-depth budget E through the closed-form segments (memoryless: after a segment of depth
// tau without a collision, E - tau is again a unit exponential), and the transmittance is a
// product of independent unbiased factors. Nothing here allocates.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "core/math.h"
#include "core/sampling/rng.h"
#include "core/sampling/unit_exponential.h"

namespace vpm {

// Work done by tracking calls (for tests and benchmarks).
struct TrackingStats {
    int64_t blocks = 0;    // majorant-walk steps (DDA cells at both levels)
    int64_t tentative = 0; // tentative collisions of delta / ratio tracking against segment majorants
    int64_t lookups = 0;   // point density lookups (the tentative collisions left after thinning)
    int64_t cells = 0;     // voxel cells whose optical depth was integrated in closed form
    int64_t exact = 0;     // segments handled in closed form
    void add(const TrackingStats& o) {
        blocks += o.blocks;
        tentative += o.tentative;
        lookups += o.lookups;
        cells += o.cells;
        exact += o.exact;
    }
};

namespace tracking {

// Ratio tracking's Russian roulette: below this weight, survive with probability T / kRrWeight
// and continue with weight kRrWeight (unbiased; bounds the work in dense media).
constexpr double kRrWeight = 1e-2;

// Whether segment s takes the closed form: its cost against the expected tentative collisions.
// An infinite scale * majorant (overflow) always takes it when there is one.
template <class Field>
inline bool use_exact(const Field& f, const typename Field::Segment& s, double mu) {
    if constexpr (Field::kHasExact) {
        return !(mu * (s.tb - s.ta) <= f.exact_cost(s));
    } else {
        (void)f, (void)s, (void)mu;
        return false;
    }
}

// Distance t in (t0, t1) of the first real collision, or kInfinity. Exactly distributed.
// Fields without closed forms need scale * majorant finite (else delta tracking cannot step).
template <class Field>
double sample_free_flight(const Field& f, double scale, double t0, double t1, Rng& rng, TrackingStats* stats) {
    if (!(scale > 0.0) || !(t1 > t0)) return kInfinity;
    double result = kInfinity;
    // Two independent unit exponentials carried from segment to segment, each drawn when first
    // needed: E, the remaining optical depth for closed-form segments, and Em, the remaining
    // majorant optical depth to the next tentative collision of delta tracking. Carrying Em
    // (instead of restarting the exponential at every segment) costs one logarithm per tentative
    // collision, not one per segment crossed.
    double E = -1.0, Em = -1.0;
    TrackingStats st;
    st.blocks = f.walk(t0, t1, [&](const typename Field::Segment& s) {
        if (!(s.majorant > 0.0)) return true;
        const double mu = scale * s.majorant;
        if constexpr (Field::kHasExact) {
            if (use_exact(f, s, mu)) {
                ++st.exact;
                if (E < 0.0) E = unit_exponential(rng);
                const double t = f.exact_sample(s, scale, E, st);
                if (t < kInfinity) {
                    result = t;
                    return false;
                }
                return true;
            }
        }
        // The majorant in force: mu up to s.tb, or after a tentative collision in a finer cell
        // (Field::local_span) that cell's majorant up to where the ray leaves it. Choosing the
        // majorant ahead from what the walk has seen so far keeps the process exact (the clock is
        // memoryless), and the finer rate saves the tentative collisions the coarse one would thin.
        double t = s.ta, rate = mu, t_span = s.tb;
        typename Field::Span span{};
        bool local = false;
        const auto back_to_segment_rate = [&] {   // from the span's end on, the segment's majorant
            t = t_span;
            rate = mu;
            t_span = s.tb;
            local = false;
        };
        for (;;) {
            if (Em < 0.0) Em = unit_exponential(rng);
            const double tau = rate * (t_span - t);
            if (!(Em < tau)) {   // no tentative collision left in this span
                Em -= tau;
                if (!local) return true;
                back_to_segment_rate();
                continue;
            }
            const double tn = t + Em / rate;
            t = tn > t ? tn : std::nextafter(t, kInfinity);   // always advance (rounding at huge t)
            Em = -1.0;
            if (!(t < t_span)) {   // rounding: the point fell at the span's end
                if (!local) return true;
                back_to_segment_rate();
                continue;
            }
            ++st.tentative;
            // Real with probability sigma_t / rate. At the segment's rate, sigma_t <= scale * the
            // local majorant, so a point with u above that is a null collision whatever the
            // density: no lookup. Either way the rest of that finer cell runs at its own rate.
            const double u = rng.uniform() * rate;
            if (!local) {
                f.local_span(s, t, span);
                const double mu_loc = scale * span.majorant;
                local = true;
                rate = mu_loc;
                t_span = span.t_end;
                if (!(u < mu_loc)) continue;
            }
            ++st.lookups;
            if (u < scale * f.density_local(s, span, t)) {   // else a null collision
                result = t;
                return false;
            }
        }
    });
    if (stats) stats->add(st);
    return result;
}

// Unbiased estimate of exp(-scale * integral_{t0}^{t1} density): exact factors exp(-tau) on
// closed-form segments, ratio tracking elsewhere, Russian roulette once the weight is small.
template <class Field>
double transmittance(const Field& f, double scale, double t0, double t1, Rng& rng, TrackingStats* stats) {
    if (!(scale > 0.0) || !(t1 > t0)) return 1.0;
    double T = 1.0, Em = -1.0;
    TrackingStats st;
    const auto roulette = [&]() {   // false: the estimate is 0, stop
        if (T < kRrWeight) {
            if (T <= 0.0 || rng.uniform() * kRrWeight >= T) {
                T = 0.0;
                return false;
            }
            T = kRrWeight;
        }
        return true;
    };
    st.blocks = f.walk(t0, t1, [&](const typename Field::Segment& s) {
        if (!(s.majorant > 0.0)) return true;
        const double mu = scale * s.majorant;
        if constexpr (Field::kHasExact) {
            if (use_exact(f, s, mu)) {
                ++st.exact;
                T *= std::exp(-scale * f.exact_depth(s, st));   // underflows to 0 in opaque media: then stop
                return roulette();
            }
        }
        for (double t = s.ta;;) {   // Em carried across segments as in sample_free_flight
            if (Em < 0.0) Em = unit_exponential(rng);
            const double tau = mu * (s.tb - t);
            if (!(Em < tau)) {
                Em -= tau;
                return true;
            }
            const double tn = t + Em / mu;
            t = tn > t ? tn : std::nextafter(t, kInfinity);
            Em = -1.0;
            if (!(t < s.tb)) return true;
            ++st.tentative;
            // Ratio tracking against the finer majorant mu_loc <= mu, whose process is this one
            // thinned with probability mu_loc / mu: the expected factor is 1 - sigma_t / mu either way.
            double mu_loc = mu;
            const double m_loc = f.local_majorant(s, t);
            if (m_loc < s.majorant) {
                mu_loc = scale * m_loc;
                if (!(rng.uniform() * mu < mu_loc)) continue;
            }
            ++st.lookups;
            T *= std::max(0.0, 1.0 - scale * f.density(s, t) / mu_loc);   // sigma_t <= mu_loc up to rounding
            if (!roulette()) return false;
        }
    });
    if (stats) stats->add(st);
    return T;
}

// --- Closed forms for fields that are cubic along a line piece (trilinear voxel cells) ---------
//
// A cubic on u in [0, 1] in Bernstein form c[0..3]. With non-negative coefficients the cubic is
// non-negative and its integral J(u) = integral_0^u is non-decreasing, which makes inversion safe.
struct CubicBernstein {
    double c[4];

    double integral() const { return 0.25 * (c[0] + c[1] + c[2] + c[3]); }
    double value(double u) const {   // de Casteljau: stable for all u in [0, 1]
        const double v = 1.0 - u;
        const double a0 = v * c[0] + u * c[1], a1 = v * c[1] + u * c[2], a2 = v * c[2] + u * c[3];
        const double b0 = v * a0 + u * a1, b1 = v * a1 + u * a2;
        return v * b0 + u * b1;
    }
    // J(u): the antiderivative is the quartic with Bernstein coefficients 0, c0/4, (c0+c1)/4, ...
    double integral_to(double u) const {
        const double d1 = 0.25 * c[0], d2 = d1 + 0.25 * c[1], d3 = d2 + 0.25 * c[2], d4 = d3 + 0.25 * c[3];
        const double v = 1.0 - u;
        const double a0 = u * d1, a1 = v * d1 + u * d2, a2 = v * d2 + u * d3, a3 = v * d3 + u * d4;
        const double b0 = v * a0 + u * a1, b1 = v * a1 + u * a2, b2 = v * a2 + u * a3;
        const double e0 = v * b0 + u * b1, e1 = v * b1 + u * b2;
        return v * e0 + u * e1;
    }
    // The u in [0, 1] with J(u) = y, for 0 <= y <= J(1): Newton on the monotone quartic,
    // safeguarded by bisection (the bracket shrinks every iteration; converges to rounding).
    double invert_integral(double y) const {
        const double total = integral();
        if (!(y > 0.0)) return 0.0;
        if (!(y < total)) return 1.0;
        double lo = 0.0, hi = 1.0, u = y / total;   // exact for a constant cubic
        for (int it = 0; it < 100; ++it) {
            const double f = integral_to(u) - y;
            if (f == 0.0) return u;
            if (f < 0.0) lo = u; else hi = u;
            const double df = value(u);
            double un = df > 0.0 ? u - f / df : 0.5 * (lo + hi);
            if (!(un > lo && un < hi)) un = 0.5 * (lo + hi);
            if (un == u || hi - lo <= 4.0 * std::numeric_limits<double>::epsilon()) return un;
            u = un;
        }
        return u;
    }
};

// The trilinear interpolant of one voxel cell along a line piece: v[dx*4 + dy*2 + dz] are the
// cell's 8 voxels (>= 0), fa and fb the piece's end points in the cell's local coordinates
// (each in [0, 1]); the result is the density on the piece as a cubic in u in [0, 1]. Built
// from the end points' convex weights, so every coefficient is a sum of non-negative products.
inline CubicBernstein trilinear_along(const double v[8], const double fa[3], const double fb[3]) {
    // x first: four linear pieces (degree 1), g[dy*2 + dz] = {value at u = 0, value at u = 1}.
    double g[4][2];
    for (int j = 0; j < 4; ++j) {
        g[j][0] = v[j] * (1.0 - fa[0]) + v[4 + j] * fa[0];
        g[j][1] = v[j] * (1.0 - fb[0]) + v[4 + j] * fb[0];
    }
    // then y: two quadratics h[dz] = g[0dz] (1 - y) + g[1dz] y (degree-1 products -> degree 2).
    double h[2][3];
    const double wy0[2] = {1.0 - fa[1], 1.0 - fb[1]}, wy1[2] = {fa[1], fb[1]};
    for (int k = 0; k < 2; ++k) {
        const double* p = g[k];       // dy = 0
        const double* q = g[2 + k];   // dy = 1
        h[k][0] = p[0] * wy0[0] + q[0] * wy1[0];
        h[k][1] = 0.5 * (p[0] * wy0[1] + p[1] * wy0[0] + q[0] * wy1[1] + q[1] * wy1[0]);
        h[k][2] = p[1] * wy0[1] + q[1] * wy1[1];
    }
    // then z: degree 2 x degree 1 -> cubic.
    const double wz0[2] = {1.0 - fa[2], 1.0 - fb[2]}, wz1[2] = {fa[2], fb[2]};
    CubicBernstein r;
    for (int i = 0; i < 4; ++i) r.c[i] = 0.0;
    for (int k = 0; k < 2; ++k) {
        const double* a = h[k];
        const double* b = k == 0 ? wz0 : wz1;
        r.c[0] += a[0] * b[0];
        r.c[1] += (2.0 * a[1] * b[0] + a[0] * b[1]) * (1.0 / 3.0);
        r.c[2] += (a[2] * b[0] + 2.0 * a[1] * b[1]) * (1.0 / 3.0);
        r.c[3] += a[2] * b[1];
    }
    return r;
}

}  // namespace tracking
}  // namespace vpm
