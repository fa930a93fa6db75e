#pragma once
// A piecewise-constant density over the sphere of directions, on an equal-area grid: columns split
// the azimuth phi = 2 pi u, rows split z = cos theta = 1 - 2 v, so every cell covers the solid angle
// 4 pi / (columns x rows) and the density in solid angle is the grid's density over the unit
// square divided by 4 pi (no sin theta factor, no pole singularity). Lights draw part of their
// photons from it (scene/emission_guides.h builds it from what each direction can reach).
#include <vector>

#include "core/math.h"
#include "core/sampling/piecewise_constant_2d.h"

namespace vpm {

class DirectionGuide {
public:
    static constexpr int kColumns = 64;
    static constexpr int kRows = 32;

    DirectionGuide() = default;
    // kRows x kColumns non-negative weights, row-major (row r spans z from 1 - 2 r / kRows down).
    explicit DirectionGuide(const std::vector<double>& weights);

    bool empty() const { return cells_.empty(); }
    // A direction from (u1, u2) in [0, 1)^2, with density pdf() (never in a cell of weight 0).
    Vec3 sample(double u1, double u2) const;
    // Density per unit solid angle of sample() at unit direction w.
    double pdf(const Vec3& w) const;

    // The direction at (du, dv) in [0, 1)^2 within cell (column, row).
    static Vec3 direction(int column, int row, double du, double dv);
    // The cell holding unit direction w.
    static void cell_of(const Vec3& w, int& column, int& row);
    static constexpr double cell_solid_angle() { return 4.0 * kPi / double(kColumns * kRows); }

private:
    PiecewiseConstant2D cells_;
};

}  // namespace vpm
