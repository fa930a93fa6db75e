#pragma once
// photons.clustering = "leave_group_out": the corrected estimate made exact for the
// clustered photons of a random walk, at the cost of one ball integral more per query.
//
// The k - 1 correction assumes the photons are independent (a Poisson process): given r_k the k - 1
// inner photons are then uniform in the ball. In a dense, bright medium one walk leaves dozens of
// collisions a mean free path or so apart; when the k-th photon's walk also put photons inside the
// ball, r_k is small exactly where they are, and the corrected sum reads high (docs/dense_bias.md:
// +0.35% .. +1.1% in the semi-infinite medium, more at small k).
//
// Every stored photon carries its walk group (photon.h: emitted index mod kWalkGroups; all photons
// of a walk share it). The groups split into two halves by parity, A and B, whose walks are
// independent of each other. With m = ceil(k / 2), let R_B be the distance of the m-th nearest
// photon of B and R_A that of A; the estimate is
//
//     S = sum_{i in A, |y_i - x| < R_B} w_i h_i(R_B) / m0(R_B)  +  (the same with A and B swapped)
//
// (m0 = integral of sigma_t over the ball, h = 1 or the local-linear weight of linear_estimate.h).
// R_B does not depend on A's photons, so given B the first term is a fixed-radius estimate of A's
// share of sigma_t L over B(x, R_B): exact in expectation however A's walks cluster; the two shares
// add up to L(x) (constant L, or linear with h). For independent photons its variance is the
// corrected estimate's at k: each term is (m - 1)-corrected-like with half the density, and
// 2 (m - 1) = k - 2. Two ball integrals per query (the earlier form, one group of 16 left out at a
// time, needed up to 16 and a second kNN gather: 1.7x the plume's render time, docs/dense_bias.md).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include <Eigen/Eigenvalues>

#include "photon/estimate/ball_extinction.h"
#include "photon/estimate/estimators.h"
#include "photon/estimate/linear_estimate.h"

namespace vpm {

struct GroupEstimate {
    Rgb value = Rgb::Zero();   // incident radiance (the sum above), when used
    bool used = false;         // false: no finite, positive radius for some half; use the plain estimate
    bool linear_fell_back = false;   // linear: the corrected sum was negative; value is the h = 1 sum (linear_estimate.h)
    size_t want = 0;           // > 0: some half's m-th photon lies beyond the list; gather this many and call again
};

inline int walk_half(uint8_t group) { return group & 1; }

// The rank m of the photon of the other half that bounds each half's ball.
inline size_t half_rank(size_t k) { return (k + 1) / 2; }

// How many neighbours to gather at once so that both halves' m-th photons are in the list for most
// queries: k plus about two standard deviations of the split of 2m photons (deterministic in k).
inline size_t leave_half_out_gather(size_t k) { return k + 2 * size_t(std::ceil(std::sqrt(double(k)))) + 4; }

// buf holds the `found` nearest photons (sorted, buf.w the weighted powers); complete: no more exist
// within max_radius (then a half with fewer than m photons bounds the other half's ball at
// max_radius). linear: h as in linear_estimate.h, else h = 1 (and h = 1 where the linear sum of the
// two halves is negative, as linear_estimate.h falls back). lookups as BallExtinction::integral.
// scale in (0, 1] (radius_schedule.h): each half's ball is that times the other half's m-th radius,
// still independent of the half it counts, so each term stays exact (docs/progressive.md). region:
// each ball's extinction over its part in the query's region (BallRegion), when not null.
inline GroupEstimate leave_half_out(const GatherBuffers& buf, size_t found, bool complete, size_t k, double max_radius,
                                    const PhotonMap& map, const Vec3& x, const BallExtinction& ball, bool linear,
                                    uint64_t* lookups = nullptr, double scale = 1.0, const BallRegion* region = nullptr) {
    GroupEstimate out;
    const size_t m = half_rank(k);
    size_t count[2] = {0, 0}, end[2] = {found, found};   // list index of each half's m-th photon
    for (size_t i = 0; i < found && (end[0] == found || end[1] == found); ++i) {
        const int h = walk_half(buf.list[i].group);
        if (++count[h] == m) end[h] = i;
    }
    if (!complete)
        for (int h = 0; h < 2; ++h)
            if (end[h] == found) {   // its m - count photons more: gather twice that many beyond the list
                out.want = found + 2 * (m - count[h]) + 8;
                return out;
            }
    double r[2];   // r[h]: the radius of half h's ball, bounded by the other half's m-th photon
    for (int h = 0; h < 2; ++h) {
        r[h] = end[1 - h] < found ? std::sqrt(buf.d2[end[1 - h]]) : max_radius;
        if (scale < 1.0) r[h] *= scale;
        if (!(r[h] > 0.0) || !std::isfinite(r[h])) return GroupEstimate{};
    }
    std::array<double, 2> m0{0.0, 0.0};
    std::array<BallMoments, 2> mo;
    if (linear) mo = ball.moments(x, r[0], r[1], lookups, region);
    else m0 = ball.integrals(x, r[0], r[1], lookups, region);
    Rgb plain = Rgb::Zero();   // the h = 1 sum, for the fallback
    for (int h = 0; h < 2; ++h) {
        const double r2 = r[h] * r[h];
        Rgb sum = Rgb::Zero(), sum_plain = Rgb::Zero();
        if (linear) {
            const BallMoments& mh = mo[size_t(h)];
            m0[size_t(h)] = mh.m0;
            Vec3 g = Vec3::Zero();   // S^-1 (c - x); exactly 0 (every h_i = 1) when the centroid is x
            if (!mh.offset.isZero(0.0)) {
                const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(mh.cov);
                if (eig.eigenvalues().minCoeff() > 1e-6 * r2)   // as linear_estimate.h
                    g = eig.eigenvectors() * (eig.eigenvalues().cwiseInverse().asDiagonal() * (eig.eigenvectors().transpose() * mh.offset));
            }
            const Vec3 c = x + mh.offset;
            if (g.isZero(0.0)) {
                for (size_t i = 0; i < found && buf.d2[i] < r2; ++i)
                    if (walk_half(buf.list[i].group) == h) sum += buf.w[i];
                sum_plain = sum;
            } else {
                for (size_t i = 0; i < found && buf.d2[i] < r2; ++i)
                    if (walk_half(buf.list[i].group) == h) {
                        sum += buf.w[i] * (1.0 - (map.position(buf.list[i].index) - c).dot(g));
                        sum_plain += buf.w[i];
                    }
            }
        } else {
            for (size_t i = 0; i < found && buf.d2[i] < r2; ++i)
                if (walk_half(buf.list[i].group) == h) sum += buf.w[i];
        }
        if (!(m0[size_t(h)] > 0.0)) return GroupEstimate{};
        out.value += sum / m0[size_t(h)];
        if (linear) plain += sum_plain / m0[size_t(h)];
    }
    if (linear && linear_sum_negative(out.value)) {
        out.value = plain;
        out.linear_fell_back = true;
    }
    out.used = true;
    return out;
}

}  // namespace vpm
