#pragma once
// Progressive radii across passes (photons.schedule = "progressive"; issue 44, derivation in
// docs/progressive.md). Any estimator whose kernel has a radius can call these: points (dim 3),
// surfaces and the beam radiance estimate (dim 2), photon beams against camera rays (dim 1).
//
// Knaus & Zwicker (TOG 2011): the measure of the kernel's support (its volume in the kernel's own
// dimension d) of 1-based pass p + 1 is that of pass p times (p + alpha) / (p + 1). With the
// 0-based pass index i used everywhere in vpm (PassContext::pass: render.first_pass counts, so a
// pass's radius depends on its index only and pass ranges merge exactly),
//
//     m_i = V_i / V_0 = Gamma(i + 1 + alpha) / (Gamma(1 + alpha) Gamma(i + 2))  ~  i^(alpha - 1) / Gamma(1 + alpha)
//
// and the radius scale is s_i = m_i^(1/d). A bias that grows like r^2 then falls like the mean of
// s_i^2 over the passes (progressive_bias_factor), the variance of the N-pass mean like N^-alpha;
// alpha = 4 / (d + 4) balances the two (mean squared error ~ N^(-4/(d+4))).
//
// kNN radii (the point and surface estimates): pass i keeps the k-th neighbour but counts the
// photons within s r_k, normalised by the volume of that smaller ball (estimators.h: exact on a
// uniform density for every k and s <= 1). progressive_knn_pass picks the smallest k >= k_floor
// (cheaper queries) whose corrected estimate's leading-order bias, proportional to
// s^2 Gamma(k - 1 + 2/d) / Gamma(k - 1), still follows m_i^(2/d) with s <= 1; below the floor only s
// shrinks, so the bias keeps falling with bounded memory and work per query.
#include <cstdint>
#include <vector>

namespace vpm {

// 4 / (d + 4): the alpha that minimises the asymptotic mean squared error for a kernel of dimension d.
constexpr double optimal_progressive_alpha(int dim) { return 4.0 / (double(dim) + 4.0); }

// m_i above (1 at pass 0, and for alpha = 1 at every pass). alpha in (0, 1], pass >= 0.
double progressive_measure_ratio(int64_t pass, double alpha);

// s_i = m_i^(1/dim): the radius of pass `pass` over pass 0's, for a kernel of dimension dim (1, 2, 3).
double progressive_radius_scale(int64_t pass, double alpha, int dim);

// Mean of s_i^2 over the passes first .. first + count - 1: an r^2 bias of the average of these
// passes over pass 0's (the predicted factor the half-space test checks).
double progressive_bias_factor(int64_t first, int64_t count, double alpha, int dim);

// One kernel that the kNN k of a pass serves: its dimension and alpha.
struct ScheduledKernel {
    int dim = 3;
    double alpha = optimal_progressive_alpha(3);
};

// Gamma(k - 1 + 2/d) / Gamma(k - 1): the corrected kNN estimate's leading-order r^2 bias at k, up to
// the density's own factor (docs/progressive.md). k >= 2.
double knn_bias_moment(int k, int dim);

// The smallest k in [min(k_floor, k), k] at which every kernel's target bias m_i^(2/d) knn_bias_moment(k, d)
// is reachable with s <= 1 (k at pass 0).
int progressive_k(int64_t pass, int k, int k_floor, const std::vector<ScheduledKernel>& kernels);

// The radius scale s <= 1 for kernel `kernel` at pass `pass` when the pass uses k_pass of the
// configured k: s^2 = m_i^(2/d) knn_bias_moment(k, d) / knn_bias_moment(k_pass, d). 1 at pass 0.
double progressive_knn_scale(int64_t pass, int k, int k_pass, const ScheduledKernel& kernel);

}  // namespace vpm
