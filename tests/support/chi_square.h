#pragma once
// Pearson's chi-square goodness-of-fit test for histograms of samples against the expected counts
// of a pdf, with cells of expected count < 5 pooled into one (the usual validity rule), and its
// p-value from the regularized upper incomplete gamma function (Numerical Recipes' series and
// continued fraction).
#include <cmath>
#include <limits>
#include <vector>

namespace vpm::test {

// Q(a, x) = Gamma(a, x) / Gamma(a), a > 0, x >= 0.
inline double gamma_q(double a, double x) {
    if (x <= 0.0) return 1.0;
    const double log_prefactor = -x + a * std::log(x) - std::lgamma(a);
    if (x < a + 1.0) {   // series for P(a, x)
        double ap = a, del = 1.0 / a, sum = del;
        for (int n = 0; n < 100000 && std::abs(del) > std::abs(sum) * 1e-16; ++n) {
            ap += 1.0;
            del *= x / ap;
            sum += del;
        }
        return 1.0 - sum * std::exp(log_prefactor);
    }
    const double tiny = 1e-300;   // continued fraction for Q(a, x) (modified Lentz)
    double b = x + 1.0 - a, c = 1.0 / tiny, d = 1.0 / b, h = d;
    for (int i = 1; i < 100000; ++i) {
        const double an = -i * (i - a);
        b += 2.0;
        d = an * d + b;
        if (std::abs(d) < tiny) d = tiny;
        c = b + an / c;
        if (std::abs(c) < tiny) c = tiny;
        d = 1.0 / d;
        const double del = d * c;
        h *= del;
        if (std::abs(del - 1.0) < 1e-16) break;
    }
    return std::exp(log_prefactor) * h;
}

struct ChiSquare {
    double statistic = 0.0;
    int dof = 0;
    double p = 1.0;
    int pooled_cells = 0;   // cells of expected count < 5 merged into one
};

// observed[i] counts against expected[i] (same total). A cell with expected 0 and observed > 0
// makes the statistic infinite (p = 0): samples where the pdf says none can be.
inline ChiSquare chi_square(const std::vector<double>& observed, const std::vector<double>& expected) {
    ChiSquare r;
    double pooled_o = 0.0, pooled_e = 0.0;
    int cells = 0;
    for (size_t i = 0; i < observed.size(); ++i) {
        if (expected[i] < 5.0) {
            pooled_o += observed[i];
            pooled_e += expected[i];
            ++r.pooled_cells;
            continue;
        }
        r.statistic += (observed[i] - expected[i]) * (observed[i] - expected[i]) / expected[i];
        ++cells;
    }
    if (r.pooled_cells > 0) {
        if (pooled_e > 0.0) {
            r.statistic += (pooled_o - pooled_e) * (pooled_o - pooled_e) / pooled_e;
            ++cells;
        } else if (pooled_o > 0.0) {
            r.statistic = std::numeric_limits<double>::infinity();
        }
    }
    r.dof = cells - 1;
    r.p = std::isfinite(r.statistic) && r.dof > 0 ? gamma_q(0.5 * r.dof, 0.5 * r.statistic) : 0.0;
    return r;
}

}  // namespace vpm::test
