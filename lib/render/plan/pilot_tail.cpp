#include "render/plan/pilot_tail.h"

#include <algorithm>
#include <cmath>
#include <functional>

#include "core/error.h"

namespace vpm {

double largest_squares_share(std::vector<double> squares, double fraction) {
    if (!(fraction > 0.0 && fraction <= 1.0)) throw Error("largest_squares_share: fraction must be in (0, 1]");
    if (squares.empty()) return 0.0;
    const size_t top = std::min(squares.size(), size_t(std::ceil(fraction * double(squares.size()))));
    // Sorted descending so that both sums add the same values in the same order on every run.
    std::sort(squares.begin(), squares.end(), std::greater<double>());
    double total = 0.0, largest = 0.0;
    for (size_t i = 0; i < squares.size(); ++i) {
        total += squares[i];
        if (i < top) largest += squares[i];
    }
    return total > 0.0 ? largest / total : 0.0;
}

double mean_of_squares_relative_se(const std::vector<double>& squares) {
    double sum = 0.0, sum_sq = 0.0;
    for (double q : squares) {
        sum += q;
        sum_sq += q * q;
    }
    if (!(sum > 0.0)) return 0.0;
    return std::sqrt(std::max(0.0, sum_sq / (sum * sum) - 1.0 / double(squares.size())));
}

}  // namespace vpm
