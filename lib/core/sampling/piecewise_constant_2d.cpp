#include "core/sampling/piecewise_constant_2d.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.h"

namespace vpm {

PiecewiseConstant1D::PiecewiseConstant1D(const std::vector<double>& weights) : weights_(weights) {
    if (weights_.empty()) throw Error("piecewise-constant distribution: no cells");
    cdf_.assign(weights_.size() + 1, 0.0);
    for (size_t i = 0; i < weights_.size(); ++i) {
        const double w = weights_[i];
        if (!(w >= 0.0) || !std::isfinite(w))
            throw Error("piecewise-constant distribution: weight " + std::to_string(i) + " is " + std::to_string(w) +
                        " (allowed: finite, >= 0)");
        cdf_[i + 1] = cdf_[i] + w;
    }
    total_ = cdf_.back();
    if (total_ > 0.0) {
        for (double& c : cdf_) c /= total_;
        // Exactly 1 at the end, and no cell whose weight is 0 may gain width from rounding.
        cdf_.back() = 1.0;
        for (size_t i = weights_.size(); i-- > 0;)
            if (weights_[i] == 0.0) cdf_[i] = cdf_[i + 1];
    } else {
        for (size_t i = 0; i < cdf_.size(); ++i) cdf_[i] = double(i) / double(weights_.size());
    }
}

size_t PiecewiseConstant1D::sample(double u, double& fraction) const {
    // The last cell whose CDF start is <= u: its interval [cdf_i, cdf_i+1) contains u and is not empty.
    const size_t i = size_t(std::upper_bound(cdf_.begin(), cdf_.end(), u) - cdf_.begin());
    const size_t cell = std::min(i == 0 ? 0 : i - 1, weights_.size() - 1);
    const double width = cdf_[cell + 1] - cdf_[cell];
    fraction = width > 0.0 ? std::min(std::max((u - cdf_[cell]) / width, 0.0), std::nextafter(1.0, 0.0)) : 0.0;
    return cell;
}

PiecewiseConstant2D::PiecewiseConstant2D(int columns, int rows, const std::vector<double>& weights)
    : columns_(columns), rows_(rows) {
    if (columns <= 0 || rows <= 0 || weights.size() != size_t(columns) * size_t(rows))
        throw Error("piecewise-constant 2D distribution: " + std::to_string(weights.size()) + " weights for " +
                    std::to_string(columns) + " x " + std::to_string(rows) + " cells");
    std::vector<double> row_sums(size_t(rows), 0.0);
    conditional_.reserve(size_t(rows));
    for (int r = 0; r < rows; ++r) {
        const auto first = weights.begin() + std::ptrdiff_t(size_t(r) * size_t(columns));
        conditional_.emplace_back(std::vector<double>(first, first + columns));
        row_sums[size_t(r)] = conditional_.back().total();
    }
    marginal_ = PiecewiseConstant1D(row_sums);
}

PiecewiseConstant2D::Sample PiecewiseConstant2D::sample(double u1, double u2) const {
    Sample s;
    double fv = 0.0, fu = 0.0;
    s.row = int(marginal_.sample(u1, fv));
    s.column = int(conditional_[size_t(s.row)].sample(u2, fu));
    s.u = (double(s.column) + fu) / double(columns_);
    s.v = (double(s.row) + fv) / double(rows_);
    s.probability = probability(s.column, s.row);
    return s;
}

double PiecewiseConstant2D::probability(int column, int row) const {
    // marginal(row) * conditional(column | row) = weight / total, computed in that order so that
    // sample() and a later lookup of the same cell give the same bits.
    return marginal_.probability(size_t(row)) * conditional_[size_t(row)].probability(size_t(column));
}

}  // namespace vpm
