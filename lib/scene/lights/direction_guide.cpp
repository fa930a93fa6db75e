#include "scene/lights/direction_guide.h"

#include <algorithm>
#include <cmath>

#include "core/sampling/turn_sincos.h"

namespace vpm {

DirectionGuide::DirectionGuide(const std::vector<double>& weights) : cells_(kColumns, kRows, weights) {}

Vec3 DirectionGuide::direction(int column, int row, double du, double dv) {
    const double u = (column + du) / kColumns, v = (row + dv) / kRows;
    const double z = 1.0 - 2.0 * v;
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    const SinCos a = sincos_turns(u);
    return Vec3(r * a.cos, r * a.sin, z);
}

void DirectionGuide::cell_of(const Vec3& w, int& column, int& row) {
    double u = std::atan2(w.y(), w.x()) / (2.0 * kPi);
    if (u < 0.0) u += 1.0;
    const double v = 0.5 * (1.0 - std::clamp(w.z(), -1.0, 1.0));
    column = std::clamp(int(u * kColumns), 0, kColumns - 1);
    row = std::clamp(int(v * kRows), 0, kRows - 1);
}

Vec3 DirectionGuide::sample(double u1, double u2) const {
    const PiecewiseConstant2D::Sample s = cells_.sample(u2, u1);   // u2 picks the row, u1 the column
    return direction(s.column, s.row, s.u * kColumns - s.column, s.v * kRows - s.row);
}

double DirectionGuide::pdf(const Vec3& w) const {
    if (empty()) return 0.0;
    int column = 0, row = 0;
    cell_of(w, column, row);
    return cells_.density(column, row) / (4.0 * kPi);
}

}  // namespace vpm
