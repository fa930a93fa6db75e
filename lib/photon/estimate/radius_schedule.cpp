#include "photon/estimate/radius_schedule.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"

namespace vpm {

namespace {

void check(int64_t pass, double alpha, int dim) {
    if (pass < 0) throw Error("radius schedule: pass " + std::to_string(pass) + " is out of range (allowed: >= 0)");
    if (!(alpha > 0.0 && alpha <= 1.0))
        throw Error("radius schedule: alpha " + std::to_string(alpha) + " is out of range (allowed: (0, 1])");
    if (dim < 1 || dim > 3)
        throw Error("radius schedule: dimension " + std::to_string(dim) + " is out of range (allowed: 1, 2, 3)");
}

}  // namespace

double progressive_measure_ratio(int64_t pass, double alpha) {
    check(pass, alpha, 1);
    if (pass == 0 || alpha == 1.0) return 1.0;
    const double i = double(pass);
    return std::exp(std::lgamma(i + 1.0 + alpha) - std::lgamma(1.0 + alpha) - std::lgamma(i + 2.0));
}

double progressive_radius_scale(int64_t pass, double alpha, int dim) {
    check(pass, alpha, dim);
    if (pass == 0 || alpha == 1.0) return 1.0;
    return std::pow(progressive_measure_ratio(pass, alpha), 1.0 / double(dim));
}

double progressive_bias_factor(int64_t first, int64_t count, double alpha, int dim) {
    check(first, alpha, dim);
    if (count < 1) throw Error("radius schedule: pass count " + std::to_string(count) + " is out of range (allowed: >= 1)");
    double sum = 0.0;
    for (int64_t i = first; i < first + count; ++i) {
        const double s = progressive_radius_scale(i, alpha, dim);
        sum += s * s;
    }
    return sum / double(count);
}

double knn_bias_moment(int k, int dim) {
    if (k < 2) throw Error("radius schedule: k = " + std::to_string(k) + " is out of range (allowed: k >= 2)");
    check(0, 1.0, dim);
    const double km1 = double(k - 1);
    return std::exp(std::lgamma(km1 + 2.0 / double(dim)) - std::lgamma(km1));
}

namespace {

// The squared radius scale target m_i^(2/d) of one kernel at `pass`.
double squared_target(int64_t pass, const ScheduledKernel& kernel) {
    const double s = progressive_radius_scale(pass, kernel.alpha, kernel.dim);
    return s * s;
}

}  // namespace

int progressive_k(int64_t pass, int k, int k_floor, const std::vector<ScheduledKernel>& kernels) {
    const int lo0 = std::max(2, std::min(k_floor, k));
    if (pass == 0 || k <= lo0 || kernels.empty()) return k;
    // Whether k' reaches every kernel's target with s <= 1; monotone in k' (the moment grows with k).
    auto reaches = [&](int kp) {
        for (const ScheduledKernel& kn : kernels)
            if (knn_bias_moment(kp, kn.dim) < squared_target(pass, kn) * knn_bias_moment(k, kn.dim)) return false;
        return true;
    };
    int lo = lo0, hi = k;   // reaches(hi) holds: the targets are at most 1
    if (reaches(lo)) return lo;
    while (hi - lo > 1) {
        const int mid = lo + (hi - lo) / 2;
        if (reaches(mid)) hi = mid;
        else lo = mid;
    }
    return hi;
}

double progressive_knn_scale(int64_t pass, int k, int k_pass, const ScheduledKernel& kernel) {
    if (pass == 0 && k_pass == k) return 1.0;
    const double s2 = squared_target(pass, kernel) * knn_bias_moment(k, kernel.dim) / knn_bias_moment(k_pass, kernel.dim);
    // k_pass from progressive_k makes s2 <= 1; a smaller k_pass would need a ball wider than r_k.
    if (!(s2 <= 1.0 + 1e-12))
        throw Error("radius schedule: k = " + std::to_string(k_pass) + " at pass " + std::to_string(pass) +
                    " would need a radius beyond the k-th neighbour's (allowed: k >= progressive_k's)");
    return std::min(1.0, std::sqrt(s2));
}

}  // namespace vpm
