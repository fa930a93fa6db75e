#include "photon/estimate/ball_extinction.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <mutex>
#include <vector>

#include "core/sampling/sampling.h"
#include "photon/estimate/mass_lattice.h"

namespace vpm {

// The mass lattice of one medium, built once by whichever thread first needs it (deterministic:
// the same cells whoever builds them), and never where no ball needs it (dense grids).
struct LazyLattice {
    std::once_flag once;
    std::unique_ptr<MassLattice> lattice;
    const MassLattice& get(const Medium& m, const Bounds3& box) {
        std::call_once(once, [&] { lattice = std::make_unique<MassLattice>(m, box); });
        return *lattice;
    }
};

namespace {

double radical_inverse(uint32_t i, uint32_t base) {
    double f = 1.0, r = 0.0;
    for (; i > 0; i /= base) {
        f /= base;
        r += f * (i % base);
    }
    return r;
}

Vec3 halton3(uint32_t i) { return Vec3(radical_inverse(i, 2), radical_inverse(i, 3), radical_inverse(i, 5)); }

constexpr int kBallPoints = 32;
constexpr BallRule kBallRule = BallRule::degree5;   // bench_ball_extinction: half the cost of halton32, and a smaller error in the blob and the plume up to 3 voxels
constexpr uint32_t kClippedPoints = 4096;
constexpr uint32_t kMassPoints = 65536;
constexpr uint64_t kCellsPerLookup = 1;   // a lattice cell or column visited costs about one grid lookup (bench_ball_extinction: 718 visits 64 us, 4096 lookups 346 us)
// A cell or column visited for the moments (first and second, per cut cell its slab's moments) costs
// about two: 68-76 ns per visit against 44 ns per lookup of the moments' 15-point rule, which the plan
// charges 40 units (1 thread, 4000 blob balls crossing the box at r = 0.26-0.35 of it, 488 visits
// each; docs/studies/march.md section 22).
constexpr uint64_t kLookupsPerMomentCell = 2;

const std::array<Vec3, kBallPoints>& unit_ball_points() {
    static const std::array<Vec3, kBallPoints> points = [] {
        std::array<Vec3, kBallPoints> p;
        for (int i = 0; i < kBallPoints; ++i) {
            const Vec3 h = halton3(uint32_t(i + 1));
            p[size_t(i)] = sample_uniform_ball(h[0], h[1], h[2]);
        }
        return p;
    }();
    return points;
}

// The first kClippedPoints points of the Halton sequence (indices 1..), computed once: the clipped
// quadrature below runs per kNN query, and the radical inverses were most of its cost.
const std::vector<Vec3>& clipped_points() {
    static const std::vector<Vec3> points = [] {
        std::vector<Vec3> p(kClippedPoints);
        for (uint32_t i = 1; i <= kClippedPoints; ++i) p[i - 1] = halton3(i);
        return p;
    }();
    return points;
}

uint64_t rule_points(BallRule rule) {
    switch (rule) {
        case BallRule::halton32: return kBallPoints;
        case BallRule::degree5: return 15;
        case BallRule::degree3: return 6;
        case BallRule::centre: return 1;
    }
    return 1;
}

// The cube of half side r about x, clipped to `box`: where a clipped ball's quadrature points go.
Bounds3 cube_in_box(const Bounds3& box, const Vec3& x, double r) {
    const Vec3 half = Vec3::Constant(r);
    Bounds3 c;
    c.lo = box.lo.cwiseMax(x - half);
    c.hi = box.hi.cwiseMin(x + half);
    return c;
}

double box_volume(const Bounds3& b) {
    if (b.empty()) return 0.0;
    const Vec3 e = b.hi - b.lo;
    return e[0] * e[1] * e[2];
}

}  // namespace

double ball_mean_by_rule(const Medium& m, const Vec3& x, double r, BallRule rule) {
    switch (rule) {
        case BallRule::centre: return m.sigma_t(x);
        case BallRule::halton32: {
            double sum = 0.0;
            for (const Vec3& p : unit_ball_points()) sum += m.sigma_t(x + r * p);
            return sum / kBallPoints;
        }
        case BallRule::degree3: {
            const double a = r * std::sqrt(0.6);
            double sum = 0.0;
            for (int i = 0; i < 3; ++i) {
                Vec3 d = Vec3::Zero();
                d[i] = a;
                sum += m.sigma_t(x + d) + m.sigma_t(x - d);
            }
            return sum / 6.0;
        }
        case BallRule::degree5: {
            const double a = r * std::sqrt(2.0 / 3.0), b = 0.5 * r;
            double axes = 0.0, diagonals = 0.0;
            for (int i = 0; i < 3; ++i) {
                Vec3 d = Vec3::Zero();
                d[i] = a;
                axes += m.sigma_t(x + d) + m.sigma_t(x - d);
            }
            for (int c = 0; c < 8; ++c)
                diagonals += m.sigma_t(x + Vec3((c & 1) ? b : -b, (c & 2) ? b : -b, (c & 4) ? b : -b));
            return (11.0 / 70.0) * m.sigma_t(x) + (9.0 / 140.0) * axes + (2.0 / 35.0) * diagonals;
        }
    }
    return m.sigma_t(x);
}

BallExtinction::BallExtinction(const std::vector<std::unique_ptr<Medium>>& media) {
    for (const auto& m : media) {
        Entry e{m.get(), m->bounds(), 0.0, Vec3::Zero(), Eigen::Matrix3d::Zero(), nullptr};
        if (m->interior_of() >= 0) {
            e.shape = RegionMask(1) << m->interior_of();
            interior_media_ = true;
        }
        const double v = box_volume(e.box);
        if (m->continuous() && v > 0.0 && std::isfinite(v)) e.lattice = std::make_shared<LazyLattice>();
        if (v > 0.0 && std::isfinite(v)) {
            double sum = 0.0;
            const Vec3 extent = e.box.hi - e.box.lo;
            // The points and their sigma_t once (the three passes below looked each up again: 2/3 of
            // the 196608 lookups every integrator and pilot paid to build this).
            std::vector<Vec3> points(kMassPoints);
            std::vector<double> sigma(kMassPoints);
            for (uint32_t i = 1; i <= kMassPoints; ++i) {
                points[i - 1] = e.box.lo + halton3(i).cwiseProduct(extent);
                sigma[i - 1] = m->sigma_t(points[i - 1]);
                sum += sigma[i - 1];
            }
            e.mass = sum * v / kMassPoints;
            if (sum > 0.0) {   // centroid and second moment for BallExtinction::moments
                Vec3 first = Vec3::Zero();
                for (uint32_t i = 0; i < kMassPoints; ++i) first += sigma[i] * points[i];
                e.centroid = first / sum;
                Eigen::Matrix3d second = Eigen::Matrix3d::Zero();
                for (uint32_t i = 0; i < kMassPoints; ++i) {
                    const Vec3 q = points[i] - e.centroid;
                    second += sigma[i] * (q * q.transpose());
                }
                e.second = second * (v / kMassPoints);
            }
        }
        entries_.push_back(e);
    }
}

// The integral of one medium's sigma_t over B(x, r) for each radius in r[0..n) (n <= 2), by the cases
// of the header. Where the clipped quadrature serves more than one radius, its points cover the
// bounding cube of the largest and are shared (one pass of lookups for all: photon/estimate/group_estimate.h
// needs two radii per query).
void BallExtinction::entry_integrals(const Entry& e, const Vec3& x, const double* r, double* out, int n, uint64_t* lookups) const {
    bool clipped[2] = {false, false};
    double r_clip = 0.0;
    for (int j = 0; j < n; ++j) {
        out[j] = 0.0;
        const double rj = r[j];
        // Is the box inside the ball? (farthest corner within r)
        const Vec3 far = (e.box.lo - x).cwiseAbs().cwiseMax((e.box.hi - x).cwiseAbs());
        if (far.squaredNorm() <= rj * rj) {
            out[j] = e.mass;
            continue;
        }
        double exact = 0.0;
        if (e.medium->ball_integral(x, rj, exact)) {   // closed form (homogeneous shapes, one grid cell)
            out[j] = exact;
            if (lookups) *lookups += 1;
            continue;
        }
        // The ball inside the box, or crossing it where sigma_t falls to 0 continuously and the ball
        // is small against the box (the points outside count 0, with no jump to resolve): the ball rule.
        const Vec3 half = Vec3::Constant(rj);
        const bool inside = e.box.contains(x - half) && e.box.contains(x + half);
        if (inside || (e.medium->continuous() && 4.0 * rj <= (e.box.hi - e.box.lo).minCoeff())) {
            const double volume = (4.0 / 3.0) * kPi * rj * rj * rj;
            out[j] = ball_mean_by_rule(*e.medium, x, rj, kBallRule) * volume;
            if (lookups) *lookups += rule_points(kBallRule);
            continue;
        }
        if (e.lattice) {
            const MassLattice& lattice = e.lattice->get(*e.medium, e.box);
            if (lattice.wide_enough(rj)) {
                uint64_t cells = 0;
                out[j] = lattice.ball_integral(x, rj, &cells);
                if (lookups) *lookups += (cells + kCellsPerLookup - 1) / kCellsPerLookup;
                continue;
            }
        }
        clipped[j] = true;
        r_clip = std::max(r_clip, rj);
    }
    if (!(r_clip > 0.0)) return;
    const Bounds3 c = cube_in_box(e.box, x, r_clip);
    const double vc = box_volume(c);
    if (!(vc > 0.0)) return;
    const Vec3 extent = c.hi - c.lo;
    double sum[2] = {0.0, 0.0};
    const double r2a = clipped[0] ? r[0] * r[0] : -1.0, r2b = n > 1 && clipped[1] ? r[1] * r[1] : -1.0;
    const double r2max = std::max(r2a, r2b);
    // The points inside the larger ball are the ones looked up (about half of the cube's), so those
    // are what is counted (docs/studies/march.md section 22).
    uint64_t looked_up = 0;
    for (const Vec3& h : clipped_points()) {
        const Vec3 p = c.lo + h.cwiseProduct(extent);
        const double d2 = (p - x).squaredNorm();
        if (d2 > r2max) continue;
        ++looked_up;
        const double s = e.medium->sigma_t(p);
        sum[0] += d2 <= r2a ? s : 0.0;   // no branch: a shell between the radii is unpredictable
        sum[1] += d2 <= r2b ? s : 0.0;
    }
    for (int j = 0; j < n; ++j)
        if (clipped[j]) out[j] = sum[j] * vc / kClippedPoints;
    if (lookups) *lookups += looked_up;
}

BallExtinction::RegionWeights BallExtinction::region_weights(const Vec3& x, const double* r, int n,
                                                             const BallRegion* region) const {
    RegionWeights w;
    if (!region) return w;
    w.on = true;
    w.region = region->region;
    bool everywhere = false;
    for (const Entry& e : entries_) everywhere = everywhere || e.shape == 0;
    if (everywhere)
        for (int j = 0; j < n; ++j) w.share[j] = region_ball_fraction(region->interfaces, x, r[j], region->region);
    return w;
}

double BallExtinction::integral(const Vec3& x, double r, uint64_t* lookups, const BallRegion* region) const {
    const RegionWeights w = region_weights(x, &r, 1, region);
    double total = 0.0;
    for (const Entry& e : entries_) {
        if (w.on && w.of(e, 0) == 0.0) continue;
        double v = 0.0;
        entry_integrals(e, x, &r, &v, 1, lookups);
        total += w.on ? w.of(e, 0) * v : v;
    }
    return total;
}

std::array<double, 2> BallExtinction::integrals(const Vec3& x, double ra, double rb, uint64_t* lookups,
                                                const BallRegion* region) const {
    std::array<double, 2> total{0.0, 0.0};
    const double r[2] = {ra, rb};
    const RegionWeights w = region_weights(x, r, 2, region);
    for (const Entry& e : entries_) {
        if (w.on && w.of(e, 0) == 0.0 && w.of(e, 1) == 0.0) continue;
        double v[2] = {0.0, 0.0};
        entry_integrals(e, x, r, v, 2, lookups);
        total[0] += w.on ? w.of(e, 0) * v[0] : v[0];
        total[1] += w.on ? w.of(e, 1) * v[1] : v[1];
    }
    return total;
}

// Sums of sigma_t, sigma_t d and sigma_t d d^T (d = p - x) over a ball.
struct BallExtinction::MomentSums {
    double s0 = 0.0;
    Vec3 s1 = Vec3::Zero();
    Eigen::Matrix3d s2 = Eigen::Matrix3d::Zero();
    void add(double w, const Vec3& d) {
        s0 += w;
        s1 += w * d;
        s2 += w * (d * d.transpose());
    }
};

bool BallExtinction::entry_moments(const Entry& e, const Vec3& x, double r, MomentSums& sums, uint64_t* lookups) const {
    double m0 = 0.0;   // a closed form (homogeneous media: scene/media/ball_clip_moments.h)
    Vec3 m1;
    Eigen::Matrix3d m2;
    if (e.medium->ball_moments(x, r, m0, m1, m2)) {
        if (lookups) *lookups += 1;
        sums.s0 += m0;
        sums.s1 += m1;
        sums.s2 += m2;
        return true;
    }
    const double volume = (4.0 / 3.0) * kPi * r * r * r;
    const Vec3 half = Vec3::Constant(r);
    const bool inside = e.box.contains(x - half) && e.box.contains(x + half);
    if (inside && !e.medium->continuous()) {
        // A medium with a jump inside its box (a homogeneous sphere's surface): 32 points and
        // their antipodes (64), so that a ball of constant sigma_t has offset exactly 0.
        const double w = volume / (2 * kBallPoints);
        if (lookups) *lookups += 2 * kBallPoints;
        for (const Vec3& p : unit_ball_points()) {
            sums.add(w * e.medium->sigma_t(x + r * p), r * p);
            sums.add(w * e.medium->sigma_t(x - r * p), -r * p);
        }
        return true;
    }
    // A continuous medium crossing its box with r <= 1/4 of the box, as integral() does: the
    // points outside count 0 and there is no jump to resolve (the clipped quadrature would take
    // 4096 points there, with an outer product each).
    if (inside || (e.medium->continuous() && 4.0 * r <= (e.box.hi - e.box.lo).minCoeff())) {
        // A continuous medium (grids, as integral() uses it): the degree-5 rule (15 points,
        // symmetric), exact for the moments up to the second of a cubic sigma_t over the ball, at
        // a quarter of the 64 points' lookups.
        const double pa = r * std::sqrt(2.0 / 3.0), pb = 0.5 * r;
        if (lookups) *lookups += rule_points(BallRule::degree5);
        sums.add(volume * (11.0 / 70.0) * e.medium->sigma_t(x), Vec3::Zero());
        for (int i = 0; i < 3; ++i) {
            Vec3 d = Vec3::Zero();
            d[i] = pa;
            sums.add(volume * (9.0 / 140.0) * e.medium->sigma_t(x + d), d);
            sums.add(volume * (9.0 / 140.0) * e.medium->sigma_t(x - d), -d);
        }
        for (int c = 0; c < 8; ++c) {
            const Vec3 d((c & 1) ? pb : -pb, (c & 2) ? pb : -pb, (c & 4) ? pb : -pb);
            sums.add(volume * (2.0 / 35.0) * e.medium->sigma_t(x + d), d);
        }
        return true;
    }
    const Vec3 far = (e.box.lo - x).cwiseAbs().cwiseMax((e.box.hi - x).cwiseAbs());
    if (far.squaredNorm() <= r * r) {   // the whole box: its precomputed moments about x
        const Vec3 c = e.centroid - x;
        sums.s0 += e.mass;
        sums.s1 += e.mass * c;
        sums.s2 += e.second + e.mass * (c * c.transpose());
        return true;
    }
    if (e.lattice) {   // a wide ball crossing a continuous medium's box: the lattice, as integral()
        const MassLattice& lattice = e.lattice->get(*e.medium, e.box);
        if (lattice.wide_enough(r)) {
            double l0 = 0.0;
            Vec3 l1;
            Eigen::Matrix3d l2;
            uint64_t cells = 0;
            lattice.ball_moments(x, r, l0, l1, l2, &cells);
            if (lookups) *lookups += kLookupsPerMomentCell * cells;
            sums.s0 += l0;
            sums.s1 += l1;
            sums.s2 += l2;
            return true;
        }
    }
    return false;
}

void BallExtinction::clipped_moments(const Entry& e, const Vec3& x, const double* r, int n, const bool* clipped, double r_clip,
                                     MomentSums* sums, uint64_t* lookups) const {
    const Bounds3 c = r_clip > 0.0 ? cube_in_box(e.box, x, r_clip) : Bounds3{};
    const double vc = r_clip > 0.0 ? box_volume(c) : 0.0;
    if (vc > 0.0) {
        const Vec3 extent = c.hi - c.lo;
        const double w = vc / kClippedPoints;
        const double r2a = clipped[0] ? r[0] * r[0] : -1.0, r2b = n > 1 && clipped[1] ? r[1] * r[1] : -1.0;
        const double r2max = std::max(r2a, r2b);
        for (const Vec3& h : clipped_points()) {
            const Vec3 p = c.lo + h.cwiseProduct(extent);
            const double d2 = (p - x).squaredNorm();
            if (d2 > r2max) continue;
            if (lookups) *lookups += 1;   // the points looked up, as entry_integrals counts them
            const double sw = w * e.medium->sigma_t(p);
            if (d2 <= r2a) sums[0].add(sw, p - x);
            if (d2 <= r2b) sums[1].add(sw, p - x);
        }
    }
}

void BallExtinction::moments_n(const Vec3& x, const double* r, int n, BallMoments* out, uint64_t* lookups,
                               const BallRegion* region) const {
    // The sums over all media, then centred; per radius, except that the clipped quadrature's points
    // cover the largest radius's cube and serve every radius that needs them (one pass of lookups).
    MomentSums total[2];
    const RegionWeights weights = region_weights(x, r, n, region);
    for (const Entry& e : entries_) {
        // A region query sums each medium's moments apart and adds them by its weight.
        MomentSums own[2];
        MomentSums* sums = weights.on ? own : total;
        if (weights.on && weights.of(e, 0) == 0.0 && (n < 2 || weights.of(e, 1) == 0.0)) continue;
        bool clipped[2] = {false, false};
        double r_clip = 0.0;
        for (int j = 0; j < n; ++j)
            if (!entry_moments(e, x, r[j], sums[j], lookups)) {
                clipped[j] = true;
                r_clip = std::max(r_clip, r[j]);
            }
        clipped_moments(e, x, r, n, clipped, r_clip, sums, lookups);
        if (weights.on)
            for (int j = 0; j < n; ++j) {
                const double wj = weights.of(e, j);
                total[j].s0 += wj * own[j].s0;
                total[j].s1 += wj * own[j].s1;
                total[j].s2 += wj * own[j].s2;
            }
    }
    for (int j = 0; j < n; ++j) {
        BallMoments& m = out[j];
        m = BallMoments{};
        m.m0 = total[j].s0;
        if (!(m.m0 > 0.0)) continue;
        m.offset = total[j].s1 / m.m0;
        m.cov = total[j].s2 / m.m0 - m.offset * m.offset.transpose();
    }
}

BallMoments BallExtinction::moments(const Vec3& x, double r, uint64_t* lookups, const BallRegion* region) const {
    BallMoments m;
    moments_n(x, &r, 1, &m, lookups, region);
    return m;
}

std::array<BallMoments, 2> BallExtinction::moments(const Vec3& x, double ra, double rb, uint64_t* lookups,
                                                   const BallRegion* region) const {
    std::array<BallMoments, 2> m;
    const double r[2] = {ra, rb};
    moments_n(x, r, 2, m.data(), lookups, region);
    return m;
}

double BallExtinction::mean(const Vec3& x, double r, uint64_t* lookups, const BallRegion* region) const {
    const double volume = (4.0 / 3.0) * kPi * r * r * r;
    return volume > 0.0 ? integral(x, r, lookups, region) / volume : 0.0;
}

}  // namespace vpm
