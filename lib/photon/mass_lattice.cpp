#include "photon/mass_lattice.h"

#include <algorithm>
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

}  // namespace

MassLattice::MassLattice(const Medium& medium, const Bounds3& box)
    : box_(box), cell_((box.hi - box.lo) / double(kCells)),
      mass_(size_t(kCells) * kCells * kCells, 0.0),
      centroid_(size_t(kCells) * kCells * kCells, Vec3::Zero()), prefix_(size_t(kCells) * kCells * (kCells + 1), 0.0) {
    const double volume = cell_[0] * cell_[1] * cell_[2] / double(kCellPoints * kCellPoints * kCellPoints);
    for (int i = 0; i < kCells; ++i)
        for (int j = 0; j < kCells; ++j) {
            double* prefix = &prefix_[column(i, j) * (kCells + 1)];
            for (int k = 0; k < kCells; ++k) {
                double sum = 0.0;
                Vec3 first = Vec3::Zero();   // sigma_t-weighted offset from the cell's centre
                for (int a = 0; a < kCellPoints; ++a)
                    for (int b = 0; b < kCellPoints; ++b)
                        for (int c = 0; c < kCellPoints; ++c) {
                            const Vec3 f((a + 0.5) / kCellPoints - 0.5, (b + 0.5) / kCellPoints - 0.5, (c + 0.5) / kCellPoints - 0.5);
                            const double s = medium.sigma_t(box.lo + (Vec3(i + 0.5, j + 0.5, k + 0.5) + f).cwiseProduct(cell_));
                            sum += s;
                            first += s * f.cwiseProduct(cell_);
                        }
                mass_[column(i, j) * kCells + size_t(k)] = sum * volume;
                centroid_[column(i, j) * kCells + size_t(k)] = sum > 0.0 ? Vec3(first / sum) : Vec3::Zero();
                prefix[k + 1] = prefix[k] + sum * volume;
            }
            total_ += prefix[kCells];
        }
}

double MassLattice::ball_integral(const Vec3& x, double r, uint64_t* cells) const {
    if (!(r > 0.0) || !(cell_.minCoeff() > 0.0)) return 0.0;
    const Vec3 rel = x - box_.lo;   // the ball's centre in the box's frame
    auto first = [&](int a) { return std::max(0, int(std::floor((rel[a] - r) / cell_[a]))); };
    auto last = [&](int a) { return std::min(kCells - 1, int(std::floor((rel[a] + r) / cell_[a]))); };
    const int i0 = first(0), i1 = last(0), j0 = first(1), j1 = last(1);
    const double r2 = r * r;
    double sum = 0.0;
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
            const int k0 = std::max(0, int(std::floor((rel[2] - hout) / cell_[2])));
            const int k1 = std::min(kCells - 1, int(std::floor((rel[2] + hout) / cell_[2])));
            int in0 = k1 + 1, in1 = k1;
            const double far2 = xf * xf + yf * yf;
            if (far2 <= r2) {
                const double hin = std::sqrt(r2 - far2);
                in0 = std::max(k0, int(std::ceil((rel[2] - hin) / cell_[2])));
                in1 = std::min(k1, int(std::floor((rel[2] + hin) / cell_[2])) - 1);
                if (in0 > in1) in0 = k1 + 1, in1 = k1;
            }
            if (in0 <= in1) sum += prefix[in1 + 1] - prefix[in0];
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
                    sum += mass[k];
                    continue;
                }
                const Vec3 n = c / dist;
                const Vec3 m = n.cwiseAbs().cwiseProduct(cell_);
                const double across = (cell_.squaredNorm() - m.squaredNorm()) / 12.0;
                // The plane is moved by the cell's centroid offset along n: where sigma_t grows across
                // the cell, more of its mass lies on that side (the blob's tails: 4% -> 1.5%).
                const double shift = n.dot(centroid_[column(i, j) * kCells + size_t(k)]);
                sum += part_below(m, r - dist - across / (2.0 * r) - shift + 0.5 * m.sum()) * mass[k];
            }
        }
    }
    if (cells) *cells += visited;
    return sum;
}

}  // namespace vpm
