#include "photon/estimate/mass_lattice.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace vpm {

namespace {

// The part of a box of projected widths m[a] = |n_a| h_a along a unit normal n that lies below the
// plane n.q = T, T measured from the box's lowest corner along n: the closed form
// sum over corners (-1)^|e| max(0, T - e.m)^3 / (6 m0 m1 m2), each width floored at 1% of the
// largest so that the cancellation stays harmless (the floor tilts the plane by at most 1%).
double part_below(Vec3 m, double T) {
    if (T <= 0.0) return 0.0;
    if (T >= m.sum()) return 1.0;
    const double floor = 1e-2 * m.maxCoeff();
    m = m.cwiseMax(floor);
    double sum = 0.0;
    for (int e = 0; e < 8; ++e) {
        const double v = T - ((e & 1) ? m[0] : 0.0) - ((e & 2) ? m[1] : 0.0) - ((e & 4) ? m[2] : 0.0);
        if (v > 0.0) sum += ((e == 0 || e == 3 || e == 5 || e == 6) ? 1.0 : -1.0) * v * v * v;
    }
    return std::clamp(sum / (6.0 * m[0] * m[1] * m[2]), 0.0, 1.0);
}

// part_below's fraction (the same number, bit for bit) and the mean (from the box's centre) and
// variance along n of that part: the distribution of u is the convolution of uniforms on [0, m_a],
// whose moments below T are sums over the same corners, of (T - a)^3 (v^4 / 8 + a v^3 / 6) and
// (v^5 / 10 + a v^4 / 4 + a^2 v^3 / 6) for v = T - a. Their cancellation with widths floored at 1%
// costs at most ~1e-10 of the cell's width squared.
double part_below_moments(Vec3 m, double T, double& mean, double& var, double& full_var) {
    mean = 0.0;
    var = 0.0;
    const double floor = 1e-2 * m.maxCoeff();
    const Vec3 mf = m.cwiseMax(floor);
    full_var = mf.squaredNorm() * (1.0 / 12.0);   // the whole (floored) box's, for the caller's scale too
    if (T <= 0.0) return 0.0;
    const double S = mf.sum();
    if (T >= m.sum()) {   // part_below's whole box (its test is on the unfloored widths)
        var = full_var;
        return 1.0;
    }
    double v0 = 0.0, v1 = 0.0, v2 = 0.0;
    for (int e = 0; e < 8; ++e) {
        const double a = ((e & 1) ? mf[0] : 0.0) + ((e & 2) ? mf[1] : 0.0) + ((e & 4) ? mf[2] : 0.0);
        const double v = T - ((e & 1) ? mf[0] : 0.0) - ((e & 2) ? mf[1] : 0.0) - ((e & 4) ? mf[2] : 0.0);   // as part_below, bit for bit
        if (!(v > 0.0)) continue;
        const double sign = (e == 0 || e == 3 || e == 5 || e == 6) ? 1.0 : -1.0;
        const double v3 = v * v * v;
        v0 += sign * v * v * v;
        v1 += sign * (v3 * v * 0.75 + a * v3);             // 6 x (v^4 / 8 + a v^3 / 6)
        v2 += sign * (v3 * v * v * 0.6 + a * v3 * v * 1.5 + a * a * v3);   // 6 x (v^5 / 10 + a v^4 / 4 + a^2 v^3 / 6)
    }
    const double part = std::clamp(v0 / (6.0 * mf[0] * mf[1] * mf[2]), 0.0, 1.0);
    if (v0 > 0.0) {
        const double inv = 1.0 / v0;   // one division for both (divisions led the lattice's profile)
        const double u1 = v1 * inv;   // the 6 P cancels
        mean = u1 - 0.5 * S;
        var = std::clamp(v2 * inv - u1 * u1, 0.0, full_var);
    }
    return part;
}

// A symmetric 3 x 3 matrix as its six entries xx, yy, zz, xy, xz, yz (half the work of a Matrix3d).
using Sym = std::array<double, 6>;
inline void add_outer(Sym& s, double w, const Vec3& d) {
    s[0] += w * d[0] * d[0], s[1] += w * d[1] * d[1], s[2] += w * d[2] * d[2];
    s[3] += w * d[0] * d[1], s[4] += w * d[0] * d[2], s[5] += w * d[1] * d[2];
}
inline void add_sym(Sym& s, double w, const Sym& t) {
    for (int i = 0; i < 6; ++i) s[i] += w * t[i];
}
// s + a b^T + b a^T
inline void add_cross(Sym& s, const Vec3& a, const Vec3& b) {
    s[0] += 2.0 * a[0] * b[0], s[1] += 2.0 * a[1] * b[1], s[2] += 2.0 * a[2] * b[2];
    s[3] += a[0] * b[1] + b[0] * a[1], s[4] += a[0] * b[2] + b[0] * a[2], s[5] += a[1] * b[2] + b[1] * a[2];
}
inline Vec3 times(const Sym& s, const Vec3& v) {
    return Vec3(s[0] * v[0] + s[3] * v[1] + s[4] * v[2], s[3] * v[0] + s[1] * v[1] + s[5] * v[2], s[4] * v[0] + s[5] * v[1] + s[2] * v[2]);
}
inline Eigen::Matrix3d full(const Sym& s) {
    Eigen::Matrix3d m;
    m << s[0], s[3], s[4], s[3], s[1], s[5], s[4], s[5], s[2];
    return m;
}

}  // namespace

MassLattice::MassLattice(const Medium& medium, const Bounds3& box)
    : box_(box), cell_((box.hi - box.lo) / double(kCells)),
      mass_(size_t(kCells) * kCells * kCells, 0.0),
      centroid_(size_t(kCells) * kCells * kCells, Vec3::Zero()), prefix_(size_t(kCells) * kCells * (kCells + 1), 0.0),
      spread_(size_t(kCells) * kCells * kCells, Sym{}),
      prefix1_(size_t(kCells) * kCells * (kCells + 1), Vec3::Zero()),
      prefix2_(size_t(kCells) * kCells * (kCells + 1), Sym{}) {
    const double volume = cell_[0] * cell_[1] * cell_[2] / double(kCellPoints * kCellPoints * kCellPoints);
    for (int i = 0; i < kCells; ++i)
        for (int j = 0; j < kCells; ++j) {
            double* prefix = &prefix_[column(i, j) * (kCells + 1)];
            Vec3* prefix1 = &prefix1_[column(i, j) * (kCells + 1)];
            Sym* prefix2 = &prefix2_[column(i, j) * (kCells + 1)];
            for (int k = 0; k < kCells; ++k) {
                double sum = 0.0;
                Vec3 first = Vec3::Zero();   // sigma_t-weighted offset from the cell's centre
                Sym second{};   // and its outer product
                for (int a = 0; a < kCellPoints; ++a)
                    for (int b = 0; b < kCellPoints; ++b)
                        for (int c = 0; c < kCellPoints; ++c) {
                            const Vec3 f((a + 0.5) / kCellPoints - 0.5, (b + 0.5) / kCellPoints - 0.5, (c + 0.5) / kCellPoints - 0.5);
                            const double s = medium.sigma_t(box.lo + (Vec3(i + 0.5, j + 0.5, k + 0.5) + f).cwiseProduct(cell_));
                            sum += s;
                            const Vec3 d = f.cwiseProduct(cell_);
                            first += s * d;
                            add_outer(second, s, d);
                        }
                const double mass = sum * volume;
                const Vec3 off = sum > 0.0 ? Vec3(first / sum) : Vec3::Zero();
                mass_[cell(i, j, k)] = mass;
                centroid_[cell(i, j, k)] = off;
                Sym spread{};
                add_sym(spread, volume, second);
                add_outer(spread, -mass, off);
                spread_[cell(i, j, k)] = spread;
                prefix[k + 1] = prefix[k] + sum * volume;
                // About the column's base point: the cell's centroid sits at (0, 0, (k + 1/2) h_z) + off.
                const Vec3 p = Vec3(0.0, 0.0, (k + 0.5) * cell_[2]) + off;
                prefix1[k + 1] = prefix1[k] + mass * p;
                prefix2[k + 1] = prefix2[k];
                add_sym(prefix2[k + 1], 1.0, spread);
                add_outer(prefix2[k + 1], mass, p);
            }
            total_ += prefix[kCells];
        }
}

template <class Run, class Cut>
uint64_t MassLattice::visit(const Vec3& x, double r, Run&& run, Cut&& cut) const {
    if (!(r > 0.0) || !(cell_.minCoeff() > 0.0)) return 0;
    const Vec3 rel = x - box_.lo;   // the ball's centre in the box's frame
    // Reciprocals once: the divisions per column and per cut cell were the visit's largest cost
    // (ball_moments 13% faster; the cell ranges and sums change only in the last bits).
    const Vec3 inv_cell = cell_.cwiseInverse();
    const double inv_2r = 0.5 / r;
    auto first = [&](int a) { return std::max(0, int(std::floor((rel[a] - r) * inv_cell[a]))); };
    auto last = [&](int a) { return std::min(kCells - 1, int(std::floor((rel[a] + r) * inv_cell[a]))); };
    const int i0 = first(0), i1 = last(0), j0 = first(1), j1 = last(1);
    const double r2 = r * r;
    uint64_t visited = 0;
    for (int i = i0; i <= i1; ++i) {
        const double x0 = i * cell_[0] - rel[0], x1 = x0 + cell_[0];   // the column's faces, relative to the centre
        const double xn = std::max(0.0, std::max(x0, -x1)), xf = std::max(std::abs(x0), std::abs(x1));
        for (int j = j0; j <= j1; ++j) {
            const double y0 = j * cell_[1] - rel[1], y1 = y0 + cell_[1];
            const double yn = std::max(0.0, std::max(y0, -y1)), yf = std::max(std::abs(y0), std::abs(y1));
            const double near2 = xn * xn + yn * yn;
            const double* prefix = &prefix_[column(i, j) * (kCells + 1)];
            if (near2 > r2 || !(prefix[kCells] > 0.0)) continue;   // outside the ball, or an empty column
            ++visited;
            // Cells the ball touches, and the run of them wholly inside (every corner within r).
            const double hout = std::sqrt(r2 - near2);
            const int k0 = std::max(0, int(std::floor((rel[2] - hout) * inv_cell[2])));
            const int k1 = std::min(kCells - 1, int(std::floor((rel[2] + hout) * inv_cell[2])));
            int in0 = k1 + 1, in1 = k1;
            const double far2 = xf * xf + yf * yf;
            if (far2 <= r2) {
                const double hin = std::sqrt(r2 - far2);
                in0 = std::max(k0, int(std::ceil((rel[2] - hin) * inv_cell[2])));
                in1 = std::min(k1, int(std::floor((rel[2] + hin) * inv_cell[2])) - 1);
                if (in0 > in1) in0 = k1 + 1, in1 = k1;
            }
            if (in0 <= in1) run(i, j, in0, in1);
            const double* mass = &mass_[column(i, j) * kCells];
            for (int k = k0; k <= k1; ++k) {
                if ((k >= in0 && k <= in1) || !(mass[k] > 0.0)) continue;   // empty cells: nothing to cut
                const double z0 = k * cell_[2] - rel[2], zn = std::max(0.0, std::max(z0, -(z0 + cell_[2])));
                if (near2 + zn * zn > r2) continue;   // the cell's nearest point is outside: the ball misses it
                ++visited;
                // The cut cell: the part of it inside the tangent plane at the sphere's point nearest its
                // centre, moved inwards by the sphere's mean sag over the cell (the mean squared offset
                // across the normal over 2r).
                const Vec3 c(x0 + 0.5 * cell_[0], y0 + 0.5 * cell_[1], k * cell_[2] - rel[2] + 0.5 * cell_[2]);
                const double dist = c.norm();
                if (!(dist > 0.0)) {
                    cut(i, j, k, Vec3::Zero(), Vec3::Zero(), 0.0);
                    continue;
                }
                const Vec3 n = c * (1.0 / dist);
                const Vec3 m = n.cwiseAbs().cwiseProduct(cell_);
                const double across = (cell_.squaredNorm() - m.squaredNorm()) * (1.0 / 12.0);
                // The plane is moved by the cell's centroid offset along n: where sigma_t grows across
                // the cell, more of its mass lies on that side (the blob's tails: 4% -> 1.5%).
                const double shift = n.dot(centroid_[cell(i, j, k)]);
                cut(i, j, k, n, m, r - dist - across * inv_2r - shift + 0.5 * m.sum());
            }
        }
    }
    return visited;
}

double MassLattice::ball_integral(const Vec3& x, double r, uint64_t* cells) const {
    double sum = 0.0;
    const uint64_t visited = visit(
        x, r, [&](int i, int j, int in0, int in1) { sum += prefix_[column(i, j) * (kCells + 1) + size_t(in1) + 1] - prefix_[column(i, j) * (kCells + 1) + size_t(in0)]; },
        [&](int i, int j, int k, const Vec3& n, const Vec3& m, double T) {
            sum += (n.isZero(0.0) ? 1.0 : part_below(m, T)) * mass_[cell(i, j, k)];
        });
    if (cells) *cells += visited;
    return sum;
}

void MassLattice::ball_moments(const Vec3& x, double r, double& m0, Vec3& m1, Eigen::Matrix3d& m2, uint64_t* cells) const {
    m0 = 0.0;
    m1 = Vec3::Zero();
    Sym s2{};
    const uint64_t visited = visit(
        x, r,
        [&](int i, int j, int in0, int in1) {
            const size_t a = column(i, j) * (kCells + 1) + size_t(in0), b = column(i, j) * (kCells + 1) + size_t(in1) + 1;
            const double mass = prefix_[b] - prefix_[a];
            const Vec3 f = prefix1_[b] - prefix1_[a];
            // From the column's base point to moments about x: s + f base^T + base f^T + mass base base^T.
            const Vec3 base = box_.lo + Vec3((i + 0.5) * cell_[0], (j + 0.5) * cell_[1], 0.0) - x;
            m0 += mass;
            m1 += f + mass * base;
            add_sym(s2, 1.0, prefix2_[b]);
            add_sym(s2, -1.0, prefix2_[a]);
            add_cross(s2, f, base);
            add_outer(s2, mass, base);
        },
        [&](int i, int j, int k, const Vec3& n, const Vec3& m, double T) {
            const size_t id = cell(i, j, k);
            Vec3 d = box_.lo + Vec3(i + 0.5, j + 0.5, k + 0.5).cwiseProduct(cell_) - x + centroid_[id];
            const Sym& spread = spread_[id];
            if (n.isZero(0.0)) {   // the whole cell
                m0 += mass_[id];
                m1 += mass_[id] * d;
                add_sym(s2, 1.0, spread);
                add_outer(s2, mass_[id], d);
                return;
            }
            double mean = 0.0, var = 0.0, full_var = 0.0;
            const double part = part_below_moments(m, T, mean, var, full_var);
            if (!(part > 0.0)) return;
            // The part below the plane: its centroid moves along n by the slab's mean, and its spread
            // along n shrinks by sqrt of the slab's variance over the whole cell's: A spread A with
            // A = I + s n n^T, i.e. spread + s (n v^T + v n^T) + s^2 (n.v) n n^T for v = spread n.
            const double s = std::sqrt(var / full_var) - 1.0;
            const Vec3 v = times(spread, n);
            const double mass = part * mass_[id];
            d += mean * n;
            m0 += mass;
            m1 += mass * d;
            add_sym(s2, part, spread);
            add_cross(s2, part * s * n, v);
            add_outer(s2, part * s * s * n.dot(v), n);
            add_outer(s2, mass, d);
        });
    m2 = full(s2);
    if (cells) *cells += visited;
}

}  // namespace vpm
