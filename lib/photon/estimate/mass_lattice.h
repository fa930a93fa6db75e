#pragma once
// The integral of a continuous medium's sigma_t over the part of a large ball inside its box, at a
// cost bounded by the lattice's size instead of the 4096 sigma_t lookups of the clipped quadrature
// (photon/estimate/ball_extinction.h). Where a light leaves a thin grid nearly empty of photons, the
// kNN balls are wide and cross the grid's box; the lattice keeps their extinction cheap
// (docs/studies/march.md).
//
// The box is cut into kCells^3 cells whose masses (integral of sigma_t) and sigma_t centroids are
// computed once, with kCellPoints^3 midpoint points each. For B(x, r): per column of cells, the run
// of cells wholly inside the ball adds its mass from a prefix sum; a cell the sphere cuts adds its
// mass times the part of it below the sphere's tangent plane at the point nearest its centre (the
// closed-form volume of a box below a plane), that plane moved inwards by the sphere's mean sag over
// the cell and against the cell's centroid offset (more of its mass lies where sigma_t is higher);
// cells outside add nothing. A deterministic rule, no noise. Measured against a 262144-point
// quadrature (tests/photon/estimate/mass_lattice_test.cpp, bench_ball_extinction): a constant box within
// 0.5% of the ball's volume from radii of 2 cells; balls of 4 cells and more in the blob and the
// plume within 0.16%, of 2 cells and more within 0.83%; the sag and the centroid shift are what
// make it so. Used for balls at least kMinCellsPerRadius cells wide (BallExtinction: those
// crossing the box beyond the ball rule's reach).
//
// ball_moments gives the same mass and the first and second sigma_t moments about x (what
// photons.extinction = "linear" needs, instead of the 4096-point clipped rule with an outer product
// per point). Whole cells add their moments from per-column prefix sums; a cut cell adds the moments of
// its part below the same plane: that slab's mean and variance along the normal in closed form,
// the cell's own sigma_t centroid and covariance across it.
#include <array>
#include <vector>

#include "core/math.h"
#include "scene/media/medium.h"

namespace vpm {

class MassLattice {
public:
    static constexpr int kCells = 16;
    static constexpr int kCellPoints = 4;   // midpoints per cell edge for the cell masses (test: the blob within 0.01%)
    static constexpr double kMinCellsPerRadius = 2.0;

    MassLattice(const Medium& medium, const Bounds3& box);
    // True when B(x, r) is wide enough for this rule (r >= kMinCellsPerRadius cells on every axis).
    bool wide_enough(double r) const { return r >= kMinCellsPerRadius * cell_.maxCoeff(); }
    // The integral of sigma_t over B(x, r) intersected with the box. cells: when not null, the cells
    // and columns visited are added to it (the cost, for the auto gather's counted work).
    double ball_integral(const Vec3& x, double r, uint64_t* cells = nullptr) const;
    // The same integral (m0, bit for bit ball_integral's) and the moments about x over the same
    // part: m1 = integral of sigma_t (p - x), m2 = integral of sigma_t (p - x)(p - x)^T.
    void ball_moments(const Vec3& x, double r, double& m0, Vec3& m1, Eigen::Matrix3d& m2, uint64_t* cells = nullptr) const;
    double total() const { return total_; }

private:
    // Calls run(i, j, in0, in1) for each column's run of whole cells and cut(i, j, k, n, m, T) for each
    // cut cell (the part of the cell of projected widths m along the unit normal n below T, measured
    // from its lowest corner along n; n = 0 for a cell whose centre is x: the whole cell), in the
    // order ball_integral sums them. Returns the columns and cells visited.
    template <class Run, class Cut>
    uint64_t visit(const Vec3& x, double r, Run&& run, Cut&& cut) const;
    size_t column(int i, int j) const { return size_t(i) * kCells + size_t(j); }
    size_t cell(int i, int j, int k) const { return column(i, j) * kCells + size_t(k); }
    Bounds3 box_;
    Vec3 cell_;
    std::vector<double> mass_;     // per cell, column-major along z: (i * kCells + j) * kCells + k
    std::vector<Vec3> centroid_;   // per cell, its sigma_t centroid's offset from its centre
    std::vector<double> prefix_;   // per column, kCells + 1 partial sums along z
    // Symmetric 3 x 3 matrices as xx, yy, zz, xy, xz, yz.
    std::vector<std::array<double, 6>> spread_;   // per cell, integral of sigma_t (p - its centroid)(p - its centroid)^T
    // Per column, kCells + 1 partial sums along z of the first and second moments about the column's
    // base point (its centre in x and y, box.lo in z).
    std::vector<Vec3> prefix1_;
    std::vector<std::array<double, 6>> prefix2_;
    double total_ = 0.0;
};

}  // namespace vpm
