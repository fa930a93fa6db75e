#pragma once
// photon/: photon records (photon.h), the photon map (photon_map.h, nanoflann), the photon
// tracer (photon_tracer.h, on the walk steps of transport/) and, here, the estimators.
//
// The kNN density estimators and the rules around them. An estimator is one function below and
// one line in the registry in estimators.cpp; everything that lists estimators (the config's
// photons.estimator, sweep axes, the study's columns) reads that registry.
//
// Inputs are the neighbours of a query sorted by distance: their weighted powers
// w_i = f(w_i, w_o) Phi_i (or unit weights in the study) and squared distances. r_k is the distance
// of the k-th nearest, V(r) the ball volume: dim 2 -> pi r^2, dim 3 -> 4/3 pi r^3.
//
//   classic     S = sum_{i=1..k}   w_i / V(r_k)                 bias +1/(k-1), needs k >= 2
//               (at k = 1 its mean is infinite, E[1/V(r_1)] diverges, and with a kernel that
//               vanishes at the rim it is identically 0: refused like the corrected k = 1)
//   corrected   S = sum_{i=1..k-1} w_i / V(r_k)                 unbiased,      needs k >= 2
//               (drops the k-th, farthest photon; infinite variance at k = 2)
//   mse_optimal S = (k-2)/(k-1) * sum_{i=1..k-1} w_i / V(r_k)   bias -1/(k-1), needs k >= 3
//
// Definition of mse_optimal for weighted photons: for unit weights it is (k-2)/V(r_k), the scale
// that minimises the MSE of c/V(r_k) (relative MSE 1/(k-1), docs/design.md section 1). We write it as
// the corrected estimate shrunk by (k-2)/(k-1) rather than as (k-2)/k * classic: both agree for
// unit weights, but the k-1 inner photons are independent of r_k given r_k while the k-th sits
// exactly on the sphere, so the corrected sum is the lower-variance base. With i.i.d. weights
// independent of position, corrected has relative variance c_w/(k-2), c_w = E[w^2]/E[w]^2, and
// the MSE-optimal shrink of it would be (k-2)/(k-2+c_w); we keep (k-2)/(k-1) (exact for equal
// weights, which is what Russian-roulette photon maps have) so the estimator needs no knowledge
// of the weight distribution. Its relative bias is -1/(k-1) for any weights.
//
// Kernels (photon/estimate/kernels.h): with a kernel K every neighbour's weight is multiplied
// by omega(t_i) = K(t_i) / n_d, t_i = r_i / r_k, so that the estimators above become
//   classic     S = sum_{i=1..k}   w_i omega(t_i) / V(r_k)       (the k-th photon kept, t_k = 1)
//   corrected   S = sum_{i=1..k-1} w_i omega(t_i) / V(r_k)       (the k-th photon discarded)
//   mse_optimal S = (k-2)/(k-2+q) * corrected,  q = E[omega^2]/E[omega]^2 over the ball
// (q = 1 for the constant kernel: (k-2)/(k-1) as above). Exact theory for a uniform density:
// given r_k the k-1 inner photons are i.i.d. uniform in the ball, so E[omega(t_i)] = m1 and the
// k-th contributes omega(1) = k1; with E[1/V(r_k)] = rho/(k-1) (any n),
//   E[S]/rho = scale * ((k-1) m1 + kept * k1) / (k-1)
// classic is unbiased iff k1 = 0 (epanechnikov, silverman, cone with slope 1), corrected for
// every properly normalised kernel (m1 = 1). The constant kernel is the default and takes
// exactly the code path it took before kernels existed.
//
// Rules for incomplete or degenerate neighbourhoods (estimate_density below; each is tested):
//  (a) fewer than k photons within a finite max_radius R: fixed-radius estimate
//      sum of all found w_i / V(R), nothing dropped (with a kernel: w_i omega(r_i / R); the
//      argument below still holds, since given the count in B(R) the photons are uniform in it).
//      R does not depend on the photons, so
//      E[sum_{x_i in B(R)} w_i] = integral of the density over B(R): unbiased for the ball mean.
//      Moreover the combination "corrected when r_k <= R, else fixed radius R" is exactly
//      unbiased for a Poisson process of intensity rho: with N = count in B(R), mu = rho V(R),
//      E[(k-1)/V(r_k); r_k <= R] = rho P(N >= k-1) and E[N/V(R); N < k] = rho P(N <= k-2), which
//      sum to rho. (tests/photon/estimate/estimators_test.cpp checks this by Monte Carlo.)
//  (b) no max_radius (infinite) and fewer than k photons exist in total: use them all, with the
//      radius at the farthest one, i.e. apply the estimator with k' = count (the kNN estimator
//      of the whole sample: V(r_n)/|R| ~ Beta(n, 1), corrected stays unbiased for a uniform
//      density). If k' is below the estimator's minimum (classic 2, corrected 2, mse_optimal 3)
//      the estimate is 0 (counted as `insufficient`). Only the farthest photon's place matters
//      here (it sets r and is the one corrected drops), so the photon-map front end passes the
//      whole map in one linear pass with the farthest last instead of sorting it
//      (PhotonMap::gather_all). The renderer does not use this rule: it never queries a map with
//      fewer than k photons and continues the camera path instead (render/photon_map/photon_map_integrator.h).
//  (c) r_k = 0 (k or more photons coincide with the query), r_k <= coincident_radius (the
//      photon map passes its position resolution: stored float positions cannot resolve smaller
//      distances, so such photons coincide as far as the map knows), or V(r_k) not a positive
//      finite number: the ball is extended to the first photon strictly farther away, at sorted position
//      m >= k (0-based), which then plays the k-th photon: the estimator is applied with
//      k' = m + 1 and r = its distance (classic sums all m+1, corrected drops that first farther
//      photon and keeps every coincident one). Counted as `extended`. If the list holds no
//      farther photon and more exist, the caller must gather more (kind need_more; the PhotonMap
//      helper does this by doubling k). If none exist: with finite max_radius, rule (a); else
//      the estimate is 0 and counted as `degenerate`. Never Inf or NaN.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <type_traits>
#include <vector>

#include "core/error.h"
#include "core/math.h"
#include "photon/estimate/kernels.h"
#include "photon/map/photon_map.h"

namespace vpm {


// --- the estimators: one function each, listed in the registry (estimators.cpp) ---------------
// An estimator sees the k nearest neighbours of a query sorted by distance (weights and squared
// distances), the radius of its ball (r_k, or R for a fixed-radius estimate) and that ball's
// volume in `dim` dimensions, so that kernel estimators fit the same signature.
template <class T>
struct Neighbours {
    const T* w = nullptr;         // weights w_i, nearest first
    const double* d2 = nullptr;   // squared distances, same order
    size_t k = 0;                 // entries used; the k-th is the farthest
    double radius = 0.0;          // r_k
    double volume = 0.0;          // V(r_k) > 0
    int dim = 3;
    const Kernel* kernel = nullptr;   // null: the constant kernel (Estimator::apply sets it)
    // Radius scale s in (0, 1] (photons.schedule = "progressive", radius_schedule.h): the estimate
    // counts the photons within s r_k over V(s r_k); 1: the estimators exactly as above.
    double scale = 1.0;
};
template <class T>
using EstimateFn = T (*)(const Neighbours<T>&);

template <class T>
inline T zero_value() { return T(0.0); }
template <>
inline Rgb zero_value<Rgb>() { return Rgb::Zero(); }

template <class T>
inline T sum_first(const T* w, size_t m) {
    T s = zero_value<T>();
    for (size_t i = 0; i < m; ++i) s += w[i];
    return s;
}

// sum_{i<m} w_i omega(t_i), t_i^2 = d2_i / radius^2; the plain sum for the constant kernel.
template <class T>
inline T kernel_sum(const Neighbours<T>& n, size_t m) {
    if (!n.kernel || n.kernel->is_constant()) return sum_first(n.w, m);
    const double inv_r2 = 1.0 / (n.radius * n.radius);
    T s = zero_value<T>();
    // u <= 1 except for rounding of r = sqrt(d2_k) squared again (one ulp): the k-th has u = 1.
    for (size_t i = 0; i < m; ++i) s += n.w[i] * n.kernel->weight(std::min(1.0, n.d2[i] * inv_r2), n.dim);
    return s;
}
inline double kernel_variance_factor(const Kernel* k, int dim) {
    return k ? k->moments(dim).variance_factor() : 1.0;
}

// Under a radius scale s < 1 (docs/progressive.md): the first m photons' weights within s r,
// each with the kernel at t = r_i / (s r), over V(s r) = s^dim V(r). Given r_k the k - 1 inner
// photons are i.i.d. uniform in B(r_k), so each lands in B(s r_k) with probability s^dim and is
// then uniform there: E[sum | r_k] = (k - 1) s^dim m1, and the s^dim cancels against the volume.
// The corrected estimate is therefore unbiased on a uniform density for every k and s.
template <class T>
inline T scaled_inner_sum(const Neighbours<T>& n, size_t m) {
    const double rs = n.scale * n.radius;
    const double rs2 = rs * rs;
    const double volume = n.volume * std::pow(n.scale, double(n.dim));
    T s = zero_value<T>();
    if (!n.kernel || n.kernel->is_constant()) {
        for (size_t i = 0; i < m && n.d2[i] <= rs2; ++i) s += n.w[i];
    } else {
        const double inv = 1.0 / rs2;
        for (size_t i = 0; i < m && n.d2[i] <= rs2; ++i) s += n.w[i] * n.kernel->weight(std::min(1.0, n.d2[i] * inv), n.dim);
    }
    return s / volume;
}
inline bool scaled(double scale) { return scale < 1.0; }

// Under a scale s < 1 each estimator keeps its own difference from corrected: classic adds the k-th
// photon's term w_k omega(1) / V(r_k) (bias k1/(k-1), as at s = 1), mse_optimal its shrink.
template <class T>
inline T estimate_classic(const Neighbours<T>& n) {
    if (scaled(n.scale)) {
        const double k1 = n.kernel ? n.kernel->weight(1.0, n.dim) : 1.0;
        return scaled_inner_sum(n, n.k - 1) + n.w[n.k - 1] * (k1 / n.volume);
    }
    return kernel_sum(n, n.k) / n.volume;
}
template <class T>
inline T estimate_corrected(const Neighbours<T>& n) {
    if (scaled(n.scale)) return scaled_inner_sum(n, n.k - 1);
    return kernel_sum(n, n.k - 1) / n.volume;   // drop the k-th (farthest) photon
}
template <class T>
inline T estimate_mse_optimal(const Neighbours<T>& n) {
    // (k-2)/(k-2+q); q = 1 exactly for the constant kernel, so k-2+q == k-1 in floating point.
    const double q = kernel_variance_factor(n.kernel, n.dim);
    if (scaled(n.scale)) return scaled_inner_sum(n, n.k - 1) * (double(n.k - 2) / (double(n.k - 2) + q));
    return kernel_sum(n, n.k - 1) * (double(n.k - 2) / ((double(n.k - 2) + q) * n.volume));
}

// Relative error, variance and MSE of an estimate of a uniform density (truth 1).
struct EstimatorTheory {
    double error = 0, variance = 0, mse = 0;
};

// What code that combines an estimator with other rules asks of it, so that no caller compares names.
struct EstimatorTraits {
    bool keeps_kth = false;            // the k-th (farthest) neighbour's weight is in the sum (classic)
    bool photon_beams = false;         // has the 1D beam form of photons.gather = "photon_beams" (the k-th kept or not)
    bool leave_group_out = false;      // has the leave-group-out form (photon/estimate/group_estimate.h)
    const char* min_k_reason = nullptr;    // why k >= min_k, for the error (null: no reason beyond the formula)
    const char* min_k_warning = nullptr;   // said where k == min_k is valid but ill-advised (null: nothing)
};

// A registry entry: what users choose by name (photons.estimator, sweep axes, study columns).
struct EstimatorEntry {
    const char* name;
    const char* formula;                  // one line for tables and --help
    size_t min_k;                         // smallest k it is defined for
    EstimateFn<double> scalar;            // the same function for unit weights (the study) ...
    EstimateFn<Rgb> rgb;                  // ... and RGB photon powers (the renderer)
    // Exact theory for n points uniform in a region, i.i.d. weights with c_w = E[w^2]/E[w]^2
    // (n = 0: the limit n -> inf), with the kernel's moments (KernelMoments{} for the constant
    // kernel); null when not known.
    EstimatorTheory (*uniform_theory)(size_t k, size_t n, double c_w, const KernelMoments& m);
    // For a constant kernel with unit weights the estimate is count(k) / V(r_k); the study's
    // quadrature theory for non-uniform densities uses it. Null for other kernels.
    double (*unit_weight_count)(size_t k);
    EstimatorTraits traits;
};

// A typed handle on one registry entry: cheap to copy and compare, never a dangling string.
class Estimator {
public:
    // Throws vpm::Error naming the allowed values.
    static Estimator named(const std::string& name);
    // Every registered estimator, in registry order (the order of study and sweep columns).
    static const std::vector<Estimator>& all();
    static std::vector<std::string> names();

    // The same estimator with kernel K (the registry's estimators use the constant kernel).
    Estimator with_kernel(const Kernel& k) const {
        Estimator e = *this;
        e.kernel_ = k;
        return e;
    }
    const Kernel& kernel() const { return kernel_; }
    // The same estimator counting within s times its ball's radius (radius_schedule.h), s in (0, 1].
    Estimator with_radius_scale(double s) const {
        if (!(s > 0.0 && s <= 1.0))
            throw Error("estimator: radius scale " + std::to_string(s) + " is out of range (allowed: (0, 1])");
        Estimator e = *this;
        e.scale_ = s;
        return e;
    }
    double radius_scale() const { return scale_; }
    // "corrected" for the constant kernel, else "corrected/epanechnikov" (kernel label).
    std::string label() const;
    // Exact uniform-density theory of this estimator with its kernel in `dim` dimensions
    // (throws vpm::Error if the entry has none).
    EstimatorTheory uniform_theory(size_t k, size_t n, double c_w, int dim) const;

    const EstimatorEntry& entry() const { return *entry_; }
    const char* name() const { return entry_->name; }
    size_t min_k() const { return entry_->min_k; }
    const EstimatorTraits& traits() const { return entry_->traits; }
    // Throws vpm::Error when k < min_k(), with the allowed range in the message.
    void validate_k(size_t k) const;
    // Non-empty warning for a valid but ill-advised choice (corrected with k = 2: infinite variance).
    std::string warning(size_t k) const;
    template <class T>
    T apply(const Neighbours<T>& n) const {
        Neighbours<T> m = n;
        m.kernel = kernel_.is_constant() ? nullptr : &kernel_;
        m.scale = scale_;
        if constexpr (std::is_same_v<T, Rgb>) return entry_->rgb(m);
        else return entry_->scalar(m);
    }
    // Rule (a): every neighbour kept, bandwidth n.radius = R.
    template <class T>
    T fixed_radius(const Neighbours<T>& n) const {
        Neighbours<T> m = n;
        m.kernel = kernel_.is_constant() ? nullptr : &kernel_;
        m.scale = scale_;
        if (scaled(scale_)) return scaled_inner_sum(m, m.k);   // every photon within s R over V(s R)
        return kernel_sum(m, m.k) / m.volume;
    }
    bool operator==(const Estimator& o) const { return entry_ == o.entry_ && kernel_ == o.kernel_ && scale_ == o.scale_; }
    bool operator!=(const Estimator& o) const { return !(*this == o); }

private:
    explicit Estimator(const EstimatorEntry* e) : entry_(e), kernel_(Kernel::constant()) {}
    const EstimatorEntry* entry_;
    Kernel kernel_;
    double scale_ = 1.0;
};

// Ball volume: dim 2 -> pi r^2, dim 3 -> 4/3 pi r^3 (throws vpm::Error for other dims).
double ball_volume(int dim, double r);

// --- the rules ----------------------------------------------------------------------------------
enum class EstimateCase {
    knn,            // >= k photons, r_k > 0: the estimator proper
    fixed_radius,   // rule (a)
    all_photons,    // rule (b), k' = count >= min k
    insufficient,   // rule (b) with too few photons for the estimator: 0
    extended,       // rule (c), ball extended to the first strictly farther photon
    degenerate,     // rule (c) with nothing farther and no max radius: 0
    empty,          // no photon found: 0
    need_more       // rule (c) needs more neighbours than the list holds (caller gathers more)
};
const char* estimate_case_name(EstimateCase c);

struct EstimatorStats {
    uint64_t queries = 0, knn = 0, fixed_radius = 0, all_photons = 0, insufficient = 0,
             extended = 0, degenerate = 0, empty = 0;
    void count(EstimateCase c);
    void merge(const EstimatorStats& o);
    std::string to_string() const;
    std::vector<std::pair<std::string, uint64_t>> fields() const;   // name, count; for tables and JSON
};

template <class T>
struct Estimate {
    T value = zero_value<T>();
    double radius = 0.0;   // radius of the ball used: the estimator's radius scale times knn_radius
    double knn_radius = 0.0;   // r_k (or R for a fixed-radius estimate) before the scale
    size_t k_used = 0;     // the k the estimator was applied with (count for fixed radius)
    EstimateCase kind = EstimateCase::empty;
};

// w[i], d2[i]: the `found` nearest photons sorted by distance. complete: no further photons exist
// (within max_radius) beyond these. max_radius: kInfinity for none. dim: 2 or 3.
// Throws vpm::Error if k < e.min_k(). stats may be null; need_more is not counted.
// coincident_radius: distances <= it count as 0 for rule (c). Under e's radius scale s < 1 every
// rule keeps its k (or R) and counts within s times its radius (rule (a): s R; docs/progressive.md).
template <class T>
Estimate<T> estimate_density(Estimator e, const T* w, const double* d2, size_t found, bool complete,
                             size_t k, double max_radius, int dim, EstimatorStats* stats = nullptr,
                             double coincident_radius = 0.0) {
    e.validate_k(k);
    Estimate<T> out;
    auto finish = [&](EstimateCase c) {
        out.kind = c;
        out.knn_radius = out.radius;
        out.radius *= e.radius_scale();   // the ball the estimate counted in (radius_schedule.h)
        if (stats && c != EstimateCase::need_more) stats->count(c);
        return out;
    };
    const bool limited = std::isfinite(max_radius);
    auto fixed = [&](EstimateCase c) {   // rule (a)
        const double v = ball_volume(dim, max_radius);
        out.radius = max_radius;
        out.k_used = found;
        if (!(v > 0.0) || !std::isfinite(v)) return finish(EstimateCase::degenerate);
        out.value = e.fixed_radius(Neighbours<T>{w, d2, found, max_radius, v, dim});
        return finish(c);
    };
    if (found == 0) {
        out.radius = limited ? max_radius : 0.0;
        return finish(EstimateCase::empty);
    }
    size_t kk = k;
    EstimateCase kind = EstimateCase::knn;
    if (found < k) {
        if (!complete) throw Error("estimate_density: fewer than k neighbours but the list is not complete");
        if (limited) return fixed(EstimateCase::fixed_radius);
        kk = found;   // rule (b)
        kind = EstimateCase::all_photons;
        if (kk < e.min_k()) {
            out.radius = std::sqrt(d2[found - 1]);
            return finish(EstimateCase::insufficient);
        }
    }
    const double c2 = coincident_radius * coincident_radius;
    auto resolvable = [&](double dd) { return dd > c2 && ball_volume(dim, std::sqrt(dd)) > 0.0; };
    double r = std::sqrt(d2[kk - 1]);
    double v = ball_volume(dim, r);
    if (!resolvable(d2[kk - 1]) || !std::isfinite(v)) {   // rule (c)
        size_t m = kk;
        while (m < found && !resolvable(d2[m])) ++m;
        if (m >= found) {
            if (!complete) return finish(EstimateCase::need_more);
            if (limited) return fixed(EstimateCase::fixed_radius);
            out.radius = r;
            out.k_used = found;
            return finish(EstimateCase::degenerate);
        }
        kk = m + 1;
        r = std::sqrt(d2[m]);
        v = ball_volume(dim, r);
        kind = EstimateCase::extended;
    }
    out.value = e.apply(Neighbours<T>{w, d2, kk, r, v, dim});
    out.radius = r;
    out.k_used = kk;
    return finish(kind);
}

// --- photon-map front end ---------------------------------------------------------------------
// Reusable per-thread buffers for estimate_in_scattering (no allocation once grown).
struct GatherBuffers {
    NeighbourList list;
    std::vector<Rgb> w;
    std::vector<double> d2;
};

// S(x, w_o) = sum hg(dot(d_p, w_o), g) Phi_p / V(r_k) with the chosen estimator and the rules above
// (dim 3). w_o is the outgoing *travel* direction of the scattered light (towards the camera:
// minus the camera ray's direction), d_p the photon's incoming travel direction (hg_eval
// convention). Convention: photons are stored at every real collision, so S is the
// collision-weighted in-scattering density and a camera ray gains albedo(x) * S per unit length.
// gather > k: gather that many neighbours at once (buf holds them all; the estimate uses the k
// nearest), for a caller that needs more of the list (photon/estimate/group_estimate.h).
Estimate<Rgb> estimate_in_scattering(const PhotonMap& map, const Vec3& x, const Vec3& w_o, double g,
                                     Estimator e, size_t k, double max_radius, GatherBuffers& buf,
                                     EstimatorStats* stats = nullptr, size_t gather = 0);

// Surface photon map (dim 2): irradiance E(x) = sum Phi_p / (pi r_k^2) with the chosen estimator
// and the rules above, over the k nearest surface photons in 3D (the standard surface photon map:
// the disc of radius r_k is assumed to lie in the surface, so corners and strongly curved surfaces
// are biased by more than the estimator's own bias). n is the unit surface normal on the side being
// shaded; a photon counts only if it arrived on that side (travel direction d_p with
// dot(d_p, n) < 0), others keep their rank but weigh 0, which removes light leaking through a
// thin wall. A Lambertian surface then reflects L_o = reflectance / pi * E.
Estimate<Rgb> estimate_surface_irradiance(const PhotonMap& map, const Vec3& x, const Vec3& n, Estimator e,
                                          size_t k, double max_radius, GatherBuffers& buf,
                                          EstimatorStats* stats = nullptr);

}  // namespace vpm
