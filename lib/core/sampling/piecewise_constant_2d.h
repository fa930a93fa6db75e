#pragma once
// Piecewise-constant distributions over [0, 1) and [0, 1)^2, sampled by inverting their CDFs
// (pbrt's Distribution1D / Distribution2D): a 2D grid of non-negative weights is sampled as a
// marginal over rows followed by a conditional over the columns of the chosen row. Cells of
// weight 0 are never returned (their CDF interval is empty), so a caller may divide by the
// probability of the cell it gets. What the weights mean (e.g. luminance times the solid angle of
// an environment-map texel) is the caller's business.
#include <cstddef>
#include <vector>

namespace vpm {

class PiecewiseConstant1D {
public:
    PiecewiseConstant1D() = default;
    // Weights must be finite and >= 0 (Error otherwise). All zero: total() == 0, and sample()
    // picks uniformly so that callers that ignore the weight still get a valid index.
    explicit PiecewiseConstant1D(const std::vector<double>& weights);

    size_t size() const { return weights_.size(); }
    double total() const { return total_; }
    // Probability of cell i (weight / total; 0 when the total is 0).
    double probability(size_t i) const { return total_ > 0.0 ? weights_[i] / total_ : 0.0; }
    // Cell for u in [0, 1), and where u fell inside its CDF interval (in [0, 1)).
    size_t sample(double u, double& fraction) const;

private:
    std::vector<double> weights_;
    std::vector<double> cdf_;   // size() + 1 entries, cdf_[0] = 0, cdf_.back() = 1
    double total_ = 0.0;
};

class PiecewiseConstant2D {
public:
    PiecewiseConstant2D() = default;
    // `weights` holds rows * columns values, row-major (row r, column c at r * columns + c).
    PiecewiseConstant2D(int columns, int rows, const std::vector<double>& weights);

    struct Sample {
        int column = 0, row = 0;
        double u = 0.0, v = 0.0;   // continuous position in [0, 1)^2 (u along columns, v along rows)
        double probability = 0.0;   // discrete probability of the cell
    };
    // u1 chooses the row (marginal), u2 the column (conditional); both in [0, 1).
    Sample sample(double u1, double u2) const;

    int columns() const { return columns_; }
    int rows() const { return rows_; }
    double total() const { return marginal_.total(); }
    bool empty() const { return !(total() > 0.0); }
    // Discrete probability of cell (column, row); sums to 1 over the grid unless empty().
    double probability(int column, int row) const;
    // Density over the unit square at a point of that cell: probability * columns * rows.
    double density(int column, int row) const { return probability(column, row) * double(columns_) * double(rows_); }

private:
    int columns_ = 0, rows_ = 0;
    std::vector<PiecewiseConstant1D> conditional_;   // one per row
    PiecewiseConstant1D marginal_;                   // row sums
};

}  // namespace vpm
