#pragma once
// photons.clustering = "leave_group_out" (issue 21): the corrected estimate made exact for the
// clustered photons of a random walk.
//
// The k - 1 correction assumes the photons are independent (a Poisson process): given r_k the k - 1
// inner photons are then uniform in the ball. In a dense, bright medium one walk leaves dozens of
// collisions a mean free path or so apart; when the k-th photon's walk also put photons inside the
// ball, r_k is small exactly where they are, and the corrected sum reads high (docs/dense_bias.md:
// +0.35% .. +1.1% in the semi-infinite medium, more at small k).
//
// Every stored photon carries its walk group (photon.h: emitted index mod kWalkGroups; all photons
// of a walk share it, and different groups are independent). For each group g with photons among the
// k nearest, let R_g be the distance of the k-th nearest photon of the OTHER groups; the estimate is
//
//     S = sum_g  sum_{i in g, |y_i - x| < R_g}  w_i h_i(R_g) / m0(R_g)
//
// (m0 = integral of sigma_t over the ball, h = 1 or the local-linear weight of linear_estimate.h).
// R_g does not depend on group g's photons, so given the other groups this is a fixed-radius
// estimate of group g's share of sigma_t L over B(x, R_g): exact in expectation however g's photons
// cluster, and summed over the groups exact for L(x) (constant L, or linear with h). Groups with no
// photon among the k nearest contribute nothing (their R_g is r_k). For independent photons it is
// the corrected estimate with k + 1. R_g takes few distinct values (ranks k .. k + a few), so the
// ball's moments are computed once per distinct radius.
#include <algorithm>
#include <array>
#include <vector>

#include "photon/ball_extinction.h"
#include "photon/estimators.h"
#include "photon/linear_estimate.h"

namespace vpm {

struct GroupEstimate {
    Rgb value = Rgb::Zero();   // incident radiance (the sum above)
    bool need_more = false;    // some R_g lies beyond the list: gather more and call again
};

// buf holds the `found` nearest photons (sorted); complete: no more exist within max_radius
// (then R_g = max_radius for a group whose k-th other photon is missing). linear: h as in
// linear_estimate.h, else h = 1. The caller checked that at least k photons were found.
inline GroupEstimate leave_group_out(const GatherBuffers& buf, size_t found, bool complete, size_t k, double max_radius,
                                     const PhotonMap& map, const Vec3& x, const BallExtinction& ball, bool linear) {
    GroupEstimate out;
    std::array<int, kWalkGroups> present{};
    for (size_t i = 0; i < k && i < found; ++i) present[buf.list[i].group] = 1;
    struct Radius {
        size_t end;      // list index of the k-th other photon (found: max_radius)
        double r;
        BallMoments m;
        Vec3 g = Vec3::Zero();   // S^-1 (c - x) for the linear weights
        bool use_g = false;
    };
    std::array<Radius, kWalkGroups> cache;   // one entry per distinct R_g (no allocation per query)
    size_t cached = 0;
    for (int group = 0; group < kWalkGroups; ++group) {
        if (!present[size_t(group)]) continue;
        size_t others = 0, end = 0;
        for (; end < found; ++end)
            if (buf.list[end].group != group && ++others == k) break;
        if (end >= found && !complete) {
            out.need_more = true;
            return out;
        }
        auto it = std::find_if(cache.begin(), cache.begin() + long(cached), [&](const Radius& c) { return c.end == end; });
        if (it == cache.begin() + long(cached)) {
            Radius c;
            c.end = end;
            c.r = end < found ? std::sqrt(buf.d2[end]) : max_radius;
            if (linear) c.m = ball.moments(x, c.r);
            else c.m.m0 = ball.integral(x, c.r);   // 32 points; the moments' 64 only for the linear weights
            if (linear) {
                const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(c.m.cov);
                c.use_g = eig.eigenvalues().minCoeff() > 1e-6 * c.r * c.r;
                if (c.use_g)
                    c.g = eig.eigenvectors() * (eig.eigenvalues().cwiseInverse().asDiagonal() * (eig.eigenvectors().transpose() * c.m.offset));
            }
            cache[cached] = c;
            it = cache.begin() + long(cached++);
        }
        if (!(it->m.m0 > 0.0)) continue;
        const double r2 = end < found ? buf.d2[end] : max_radius * max_radius;
        const Vec3 centroid = x + it->m.offset;
        Rgb sum = Rgb::Zero();
        for (size_t i = 0; i < end; ++i) {
            if (buf.list[i].group != group || !(buf.d2[i] < r2)) continue;
            const double h = it->use_g ? 1.0 - (map.position(buf.list[i].index) - centroid).dot(it->g) : 1.0;
            sum += buf.w[i] * h;
        }
        out.value += sum / it->m.m0;
    }
    return out;
}

}  // namespace vpm
