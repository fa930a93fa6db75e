// Issue 21 (docs/dense_bias.md): where the corrected estimate's excess in dense, bright media comes
// from. Not a Google Benchmark: one table per run.
//
// An exactly semi-infinite, laterally periodic (tile W x W), isotropic half-space (sigma_t = 1, so
// lengths are mean free paths) lit straight down by unit irradiance. Photons are traced here, not by
// vpm's tracer (NEE convention: collisions after the first scattering are stored with the power
// arriving; roulette on the albedo), so the truth is Chandrasekhar's closed form minus single
// scattering, and this map's own depth histogram is an unbiased, kNN-free estimate of the same
// number: the PAIRED line divides each variant by it, which cancels most of the map's noise.
// Query points are where a camera looking straight down collides (depth ~ Exp(1), lateral uniform),
// and every variant below is evaluated on the same map and the same queries:
//   corrected/ball        sum_{k-1} / (sigma_t |B(r_k) n medium|)   (vpm's photons.extinction = "ball")
//   corrected/point       the same over the full ball volume         ("point")
//   classic/ball          sum_k
//   leave-walk-out/ball   each walk's photons within the k-th photon of the other walks
//   corrected k+1/ball    its limit for independent photons
//   corrected/halton4096  the ball's volume by vpm's 4096-point clipped quadrature
//   corrected/32pt rnd plane  by vpm's 32-point ball quadrature, boundary at a random orientation
//   linear                the local-linear weights of photon/estimate/linear_estimate.h
//   leave-16-groups-out   photon/estimate/group_estimate.h (walk index mod 16)
//   linear+16 groups      both
//   leave-half-out        each parity half of the walks within the other half's ceil(k/2)-th photon
//                         (photon/estimate/group_estimate.h since the second session of issue 21)
//   linear+halves         both
// --shuffle 1 moves every photon to a random lateral place (depth kept): no clustering, same profile.
// SMOOTHING: the linear estimates' expectation if their only error were the curvature of the depth
// profile across each query's realised ball (this map's fine histogram in place of the truth).
//
//   bench_dense_bias [--albedo 0.99] [--photons 1e5] [--width 20] [--k 32] [--queries 2e5]
//                    [--seed 1] [--mu 1] [--store 1] [--shuffle 0] [--margin 1.5]
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <string>
#include <vector>

#include <nanoflann.hpp>

#include "analysis/study/chandrasekhar_h.h"
#include "core/sampling/rng.h"

using namespace vpm;

namespace {
constexpr double kPi_ = 3.14159265358979323846;

struct Cloud {
    std::vector<double> x, y, d;   // lateral x, y in [0, W), depth d > 0
    std::vector<double> p;         // power
    std::vector<uint32_t> walk;
    size_t kdtree_get_point_count() const { return x.size(); }
    double kdtree_get_pt(size_t i, size_t dim) const { return dim == 0 ? x[i] : dim == 1 ? y[i] : d[i]; }
    template <class B> bool kdtree_get_bbox(B&) const { return false; }
};
using Tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, Cloud>, Cloud, 3>;

double ball_volume(double r) { return 4.0 / 3.0 * kPi_ * r * r * r; }
// |B(r) at depth d  intersect  {depth > 0}|
double clipped_volume(double d, double r) {
    if (d >= r) return ball_volume(r);
    const double h = r - d;   // cap height above the surface
    return ball_volume(r) - kPi_ * h * h * (3.0 * r - h) / 3.0;
}

void trace(Cloud& c, uint64_t n, double albedo, double W, uint64_t seed, double store_p) {
    Rng rng(seed, 7);
    const double power = W * W / double(n);   // irradiance 1 over the tile
    for (uint64_t i = 0; i < n; ++i) {
        double x = rng.uniform() * W, y = rng.uniform() * W, d = 0.0;
        double dx = 0, dy = 0, dd = 1;
        bool scattered = false;
        for (;;) {
            const double t = -std::log(1.0 - rng.uniform());
            x += t * dx; y += t * dy; d += t * dd;
            if (d <= 0.0) break;
            if (scattered && (store_p >= 1.0 || rng.uniform() < store_p)) {
                c.x.push_back(x - W * std::floor(x / W));
                c.y.push_back(y - W * std::floor(y / W));
                c.d.push_back(d);
                c.p.push_back(power / std::min(1.0, store_p));
                c.walk.push_back(uint32_t(i));
            }
            if (rng.uniform() >= albedo) break;
            scattered = true;
            const double z = 1.0 - 2.0 * rng.uniform(), phi = 2.0 * kPi_ * rng.uniform(), s = std::sqrt(std::max(0.0, 1.0 - z * z));
            dx = s * std::cos(phi); dy = s * std::sin(phi); dd = z;
        }
    }
}

double radical_inverse(uint32_t i, uint32_t base) {
    double f = 1.0, r = 0.0;
    for (; i > 0; i /= base) { f /= base; r += f * (i % base); }
    return r;
}
// vpm's 32-point ball quadrature (photon/estimate/ball_extinction.cpp): Halton (2, 3, 5) warped into the ball.
std::vector<std::array<double, 3>> ball_points() {
    std::vector<std::array<double, 3>> p;
    for (uint32_t i = 1; i <= 32; ++i) {
        const double u1 = radical_inverse(i, 2), u2 = radical_inverse(i, 3), u3 = radical_inverse(i, 5);
        const double z = 1.0 - 2.0 * u1, rr = std::sqrt(std::max(0.0, 1.0 - z * z)), phi = 2.0 * kPi_ * u2, c = std::cbrt(u3);
        p.push_back({c * rr * std::cos(phi), c * rr * std::sin(phi), c * z});
    }
    return p;
}
// vpm's clipped quadrature for an axis-aligned face: 4096 Halton points over the cube clipped at depth 0.
double clipped_volume_halton(double d, double r) {
    if (d >= r) return ball_volume(r);
    const double lo = 0.0, hi = d + r;   // depth range of the clipped cube, relative: point depth in [0, d + r]
    int in = 0;
    for (uint32_t i = 1; i <= 4096; ++i) {
        const double px = (radical_inverse(i, 2) * 2 - 1) * r, py = (radical_inverse(i, 3) * 2 - 1) * r;
        const double pd = lo + radical_inverse(i, 5) * (hi - lo);
        if (px * px + py * py + (pd - d) * (pd - d) <= r * r) ++in;
    }
    return double(in) / 4096.0 * (2 * r) * (2 * r) * (hi - lo);
}

// depth moments of the clipped ball: centroid depth and variance (slices, 400 midpoints)
void clipped_moments(double d, double r, double& cd, double& vd) {
    const double lo = std::max(0.0, d - r), hi = d + r;
    const int n = 400;
    double m0 = 0, m1 = 0, m2 = 0;
    for (int i = 0; i < n; ++i) {
        const double z = lo + (i + 0.5) * (hi - lo) / n, a = std::max(0.0, r * r - (z - d) * (z - d));
        m0 += a; m1 += a * z; m2 += a * z * z;
    }
    cd = m1 / m0;
    vd = m2 / m0 - cd * cd;
}
// the local-linear weight of a photon at depth y for a ball of radius r at depth d (1 for whole balls)
double linear_h(double y, double d, double r) {
    if (d >= r) return 1.0;
    double cd, vd;
    clipped_moments(d, r, cd, vd);
    return 1.0 - (y - cd) * (cd - d) / vd;
}

struct Acc {
    double s = 0, s2 = 0; long n = 0;
    void add(double v) { s += v; s2 += v * v; ++n; }
    double mean() const { return s / n; }
    double se() const { return std::sqrt(std::max(0.0, (s2 / n - mean() * mean())) / (n - 1)); }
};

}  // namespace

int main(int argc, char** argv) {
    double albedo = 0.99, W = 20, mu = 1.0;
    uint64_t n = 1000000, queries = 200000, seed = 1;
    size_t k = 32;
    double store_p = 1.0, margin = 1.5;   // periodic copies within margin mean free paths of the tile's edges
    bool shuffle = false;
    for (int i = 1; i + 1 < argc; i += 2) {
        const std::string a = argv[i];
        const double v = std::atof(argv[i + 1]);
        if (a == "--albedo") albedo = v; else if (a == "--width") W = v; else if (a == "--photons") n = uint64_t(v);
        else if (a == "--queries") queries = uint64_t(v); else if (a == "--k") k = size_t(v); else if (a == "--seed") seed = uint64_t(v);
        else if (a == "--mu") mu = v; else if (a == "--store") store_p = v; else if (a == "--shuffle") shuffle = v != 0;
        else if (a == "--margin") margin = v;
    }
    Cloud c;
    trace(c, n, albedo, W, seed, store_p);
    Rng srng(seed, 99);
    if (shuffle)   // keep each depth, randomise the lateral place: no clustering, same depth profile
        for (size_t i = 0; i < c.x.size(); ++i) { c.x[i] = srng.uniform() * W; c.y[i] = srng.uniform() * W; c.walk[i] = uint32_t(i); }
    const size_t stored = c.x.size();
    for (size_t i = 0; i < stored; ++i)
        for (int ox = -1; ox <= 1; ++ox)
            for (int oy = -1; oy <= 1; ++oy) {
                if (!ox && !oy) continue;
                const double x = c.x[i] + ox * W, y = c.y[i] + oy * W;
                if (x < -margin || x > W + margin || y < -margin || y > W + margin) continue;
                c.x.push_back(x); c.y.push_back(y); c.d.push_back(c.d[i]); c.p.push_back(c.p[i]); c.walk.push_back(c.walk[i]);
            }
    const ChandrasekharH h(albedo);
    const double truth = (h.reflected(mu, 1.0) - h.single_scattering(mu, 1.0));   // multiple-scattering radiance
    // histogram truth: L_ms = a/(4 pi) int C(d) e^{-d/mu} dd / mu = a/(4 pi) sum p e^{-d/mu} / (mu W^2)
    double hist = 0;
    for (size_t i = 0; i < stored; ++i) hist += c.p[i] * std::exp(-c.d[i] / mu);
    hist *= albedo / (4 * kPi_) / (mu * W * W);
    // fine depth histogram of the collision density C(d) (power per volume), bins of 0.01 mfp
    const double bw = 0.01;
    std::vector<double> chist(20000, 0.0);
    for (size_t i = 0; i < stored; ++i) { const size_t b = size_t(c.d[i] / bw); if (b < chist.size()) chist[b] += c.p[i] / (bw * W * W); }
    auto c_at = [&](double d) { const size_t b = size_t(d / bw); return b < chist.size() ? chist[b] : 0.0; };
    double clip_excess = 0, inner_excess = 0, c_total = 0;
    Tree tree(3, c, nanoflann::KDTreeSingleIndexAdaptorParams(10));
    tree.buildIndex();
    const size_t M = 4 * k + 64;
    std::vector<unsigned> idx(M);
    std::vector<double> d2(M);
    // variants: 0 corrected clipped (ball), 1 corrected point (full ball), 2 classic clipped,
    // 3 leave-one-walk-out clipped, 4 corrected clipped with k+1 (LOWO's no-cluster limit)
    const int V = 12;
    const char* names[V] = {"corrected/ball", "corrected/point", "classic/ball", "leave-walk-out/ball", "corrected k+1/ball", "corrected/halton4096", "corrected/32pt rnd plane", "linear", "leave-16-groups-out", "linear+16 groups", "leave-half-out", "linear+halves"};
    const auto bp = ball_points();
    std::vector<Acc> acc(V);
    // The deterministic smoothing of this map's own depth profile by each query's realised ball(s):
    // the estimate's expectation if its only error were the profile's curvature across the ball
    // (the fine histogram C stands for the truth; linear in C, so unbiased for the smoothed truth).
    //   pred linear        integral of h C over B(r_k) n medium / |B(r_k) n medium|
    //   pred linear+halves the same at each half's radius, each half weighing 1/2
    Acc pred_lin, pred_lin_halves, at_query;
    auto smoothed = [&](double dq, double r) {
        const double lo = std::max(0.0, dq - r), hi = dq + r;
        double cd = dq, vd = 1.0;   // linear_h's moments, once per ball
        if (dq < r) clipped_moments(dq, r, cd, vd);
        double num = 0;
        for (size_t b = size_t(lo / bw); b < chist.size() && b * bw < hi; ++b) {
            const double z0 = std::max(lo, b * bw), z1 = std::min(hi, (b + 1) * bw);
            if (!(z1 > z0)) continue;
            const double z = 0.5 * (z0 + z1), a = kPi_ * std::max(0.0, r * r - (z - dq) * (z - dq));
            num += chist[b] * (dq < r ? 1.0 - (z - cd) * (cd - dq) / vd : 1.0) * a * (z1 - z0);
        }
        return num / clipped_volume(dq, r);
    };
    // depth profile of the bias: bins of d_q / r_k
    const int B = 8;
    std::vector<Acc> bin_est(B), bin_true(B);
    Rng rng(seed, 1234);
    const double scale = albedo / (4 * kPi_);
    long lowo_short = 0;
    double r_sum = 0;
    std::vector<char> mark;
    for (uint64_t q = 0; q < queries; ++q) {
        const double dq = -mu * std::log(1.0 - rng.uniform());   // the camera's collision depth, pdf e^{-d/mu}/mu
        const double pt[3] = {rng.uniform() * W, rng.uniform() * W, dq};
        const size_t found = tree.knnSearch(pt, M, idx.data(), d2.data());
        if (found < M) { std::fprintf(stderr, "short list\n"); return 1; }
        const double rk = std::sqrt(d2[k - 1]);
        if (std::sqrt(d2[found - 1]) > margin) { std::fprintf(stderr, "list beyond the periodic margin\n"); return 1; }
        r_sum += rk;
        double s_in = 0;
        for (size_t i = 0; i + 1 < k; ++i) s_in += c.p[idx[i]];
        const double vclip = clipped_volume(dq, rk);
        double est[V];
        est[0] = s_in / vclip;
        est[1] = s_in / ball_volume(rk);
        est[2] = (s_in + c.p[idx[k - 1]]) / vclip;
        {   // leave one walk out
            double sum = 0;
            std::map<uint32_t, int> seen;
            for (size_t i = 0; i < k; ++i) seen[c.walk[idx[i]]]++;
            for (const auto& [w, cnt] : seen) {
                size_t others = 0, j = 0;
                for (; j < found; ++j) if (c.walk[idx[j]] != w && ++others == k) break;
                if (j >= found) { ++lowo_short; continue; }
                const double R2 = d2[j];
                double pw = 0;
                for (size_t i = 0; i < j; ++i) if (c.walk[idx[i]] == w && d2[i] < R2) pw += c.p[idx[i]];
                sum += pw / clipped_volume(dq, std::sqrt(R2));
            }
            est[3] = sum;
        }
        {
            double s2 = s_in + c.p[idx[k - 1]];
            est[4] = s2 / clipped_volume(dq, std::sqrt(d2[k]));
        }
        est[5] = s_in / clipped_volume_halton(dq, rk);
        {   // a plane of random orientation through the same cut: the 32 points count the inside part
            const double z = 1.0 - 2.0 * rng.uniform(), phi = 2.0 * kPi_ * rng.uniform(), rr = std::sqrt(std::max(0.0, 1 - z * z));
            const double nx = rr * std::cos(phi), ny = rr * std::sin(phi), nz = z;
            int in = 0;
            for (const auto& p : bp) if (dq + rk * (p[0] * nx + p[1] * ny + p[2] * nz) > 0.0) ++in;
            est[6] = in > 0 ? s_in / (ball_volume(rk) * in / 32.0) : s_in / vclip;
        }
        {
            double sl = 0;
            for (size_t i = 0; i + 1 < k; ++i) sl += c.p[idx[i]] * linear_h(c.d[idx[i]], dq, rk);
            est[7] = sl / vclip;
        }
        for (int lin = 0; lin < 2; ++lin) {   // leave one of 16 walk groups out
            double sum = 0;
            bool present[16] = {};
            for (size_t i = 0; i < k; ++i) present[c.walk[idx[i]] % 16] = true;
            for (uint32_t g = 0; g < 16; ++g) {
                if (!present[g]) continue;
                size_t others = 0, j = 0;
                for (; j < found; ++j) if (c.walk[idx[j]] % 16 != g && ++others == k) break;
                if (j >= found) { ++lowo_short; continue; }
                const double R = std::sqrt(d2[j]);
                double pw = 0;
                for (size_t i = 0; i < j; ++i) if (c.walk[idx[i]] % 16 == g && d2[i] < d2[j]) pw += c.p[idx[i]] * (lin ? linear_h(c.d[idx[i]], dq, R) : 1.0);
                sum += pw / clipped_volume(dq, R);
            }
            est[8 + lin] = sum;
        }
        double half_pred = 0;
        for (int lin = 0; lin < 2; ++lin) {   // photon/estimate/group_estimate.h: each parity half within the other's m-th photon
            const size_t m = (k + 1) / 2;
            size_t cnt[2] = {0, 0}, end[2] = {found, found};
            for (size_t j = 0; j < found; ++j) { const int h = int(c.walk[idx[j]] % 2); if (++cnt[h] == m && end[h] == found) end[h] = j; }
            double sum = 0;
            for (int h = 0; h < 2; ++h) {
                const size_t j = end[1 - h];
                if (j >= found) { ++lowo_short; continue; }
                const double R = std::sqrt(d2[j]);
                if (lin) half_pred += 0.5 * smoothed(dq, R);
                double pw = 0;
                for (size_t i = 0; i < j; ++i) if (int(c.walk[idx[i]] % 2) == h && d2[i] < d2[j]) pw += c.p[idx[i]] * (lin ? linear_h(c.d[idx[i]], dq, R) : 1.0);
                sum += pw / clipped_volume(dq, R);
            }
            est[10 + lin] = sum;
        }
        for (int v = 0; v < V; ++v) acc[v].add(scale * est[v]);
        pred_lin.add(scale * smoothed(dq, rk));
        pred_lin_halves.add(scale * half_pred);
        at_query.add(scale * c_at(dq));
        const double ct = scale * c_at(dq);
        c_total += ct;
        (dq < rk ? clip_excess : inner_excess) += scale * est[0] - ct;
        const int b = std::min(B - 1, int(dq / rk * 4));
        bin_est[b].add(scale * est[0]);
    }
    std::printf("albedo %.3f mu %.2f photons %llu stored %zu (%.1f per walk) W %.0f k %zu queries %llu mean r_k %.4f mfp store_p %.3f shuffle %d\n",
                albedo, mu, (unsigned long long)n, stored, double(stored) / n, W, k, (unsigned long long)queries, r_sum / queries, store_p, int(shuffle));
    std::printf("PAIRED (estimate / this map's histogram):");
    for (int v = 0; v < V; ++v) std::printf(" %s %.4f +- %.4f;", names[v], acc[v].mean() * truth / hist / truth, acc[v].se() / hist);
    std::printf("\n");
    std::printf("SMOOTHING (this map's depth profile averaged over each query's realised balls, / histogram): linear %.4f +- %.4f; linear+halves %.4f +- %.4f; profile at the query depths %.4f +- %.4f\n",
                pred_lin.mean() / hist, pred_lin.se() / hist, pred_lin_halves.mean() / hist, pred_lin_halves.se() / hist, at_query.mean() / hist, at_query.se() / hist);
    std::printf("truth (closed form, multiple scattering) %.6f   histogram of this map %.6f (%.4f)\n", truth, hist, hist / truth);
    for (int v = 0; v < V; ++v)
        std::printf("  %-22s %.6f +- %.6f   / truth %.4f +- %.4f\n", names[v], acc[v].mean(), acc[v].se(), acc[v].mean() / truth, acc[v].se() / truth);
    std::printf("  excess of corrected/ball against the depth histogram at each query: clipped balls (d_q < r_k) %+.4f, whole balls %+.4f (of the mean)\n", clip_excess / c_total, inner_excess / c_total);
    if (lowo_short) std::printf("  leave-walk-out lists too short: %ld\n", lowo_short);
    std::printf("  corrected/ball by d_q / r_k bins of 0.25: share of queries and mean estimate / truth-mean-of-all\n   ");
    for (int b = 0; b < B; ++b) std::printf(" [%d] %.3f %.3f", b, double(bin_est[b].n) / queries, bin_est[b].n ? bin_est[b].mean() / truth : 0.0);
    std::printf("\n");
}
