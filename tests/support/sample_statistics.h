#pragma once
// A running mean with its standard error, for the statistical tests of every folder.
#include <algorithm>
#include <cmath>

namespace vpm::test {

// Mean of n independent values and the standard error of that mean.
struct Sample {
    double sum = 0, sum2 = 0;
    int n = 0;
    void add(double v) {
        sum += v;
        sum2 += v * v;
        ++n;
    }
    double mean() const { return sum / n; }
    double var() const { return std::max(0.0, sum2 / n - mean() * mean()) * n / (n - 1); }   // of the values
    double se() const { return std::sqrt(std::max(0.0, sum2 / n - mean() * mean()) / (n - 1)); }
};

}  // namespace vpm::test
