#include "photon/estimate/estimators.h"

#include <algorithm>
#include <sstream>

#include "core/henyey_greenstein.h"
#include "core/registry.h"

namespace vpm {

namespace {

// Constant kernel keeping `kept` of the k nearest, scaled by `scale`: for n uniform points
// (density 1) U = V(r_k)/|R| ~ Beta(k, n-k+1), E[1/U] = n/(k-1), E[1/U^2] = n(n-1)/((k-1)(k-2)),
// and given r_k the inner k-1 points are i.i.d. uniform in the ball, so with i.i.d. weights
// E[S] = scale kept/(k-1) and E[S^2] = scale^2 kept (c_w + kept - 1) (n-1)/n / ((k-1)(k-2)).
EstimatorTheory constant_kernel_theory(double kept, double scale, size_t k, size_t n, double c_w) {
    const double kk = double(k);
    const double f = n > 0 ? double(n - 1) / double(n) : 1.0;
    const double mean = scale * kept / (kk - 1.0);
    EstimatorTheory t;
    t.error = mean - 1.0;
    t.variance = t.mse = kInfinity;
    if (k > 2) {
        const double m2 = scale * scale * kept * (c_w + kept - 1.0) * f / ((kk - 1.0) * (kk - 2.0));
        t.variance = m2 - mean * mean;
        t.mse = t.variance + t.error * t.error;
    }
    return t;
}

// Kernel with relative weight omega (moments m1 = E[omega], m2 = E[omega^2] over the ball,
// k1 = omega(1)), the k-th photon kept (keep = 1) or discarded (0), the sum scaled by `scale`.
// Given r_k the k-1 inner photons are i.i.d. uniform in the ball and the k-th lies on the
// sphere, so with i.i.d. weights (E[w] = 1, E[w^2] = c_w) independent of position, Z = the
// weighted kernel sum has
//   E[Z | r_k]   = (k-1) m1 + keep k1
//   E[Z^2 | r_k] = (k-1) c_w m2 + (k-1)(k-2) m1^2 + keep (2 (k-1) m1 k1 + c_w k1^2)
// and S = scale Z / V(r_k) with E[1/V] = rho/(k-1), E[1/V^2] = rho^2 (n-1)/n / ((k-1)(k-2)).
// The constant kernel (m1 = m2 = k1 = 1) reduces to constant_kernel_theory, which it uses.
EstimatorTheory kernel_theory(bool keep, double scale, size_t k, size_t n, double c_w, const KernelMoments& m) {
    const double kk = double(k);
    if (m.constant) return constant_kernel_theory(keep ? kk : kk - 1.0, scale, k, n, c_w);
    const double f = n > 0 ? double(n - 1) / double(n) : 1.0;
    const double kp = keep ? 1.0 : 0.0;
    const double mean = scale * ((kk - 1.0) * m.m1 + kp * m.k1) / (kk - 1.0);
    EstimatorTheory t;
    t.error = mean - 1.0;
    t.variance = t.mse = kInfinity;
    if (k > 2) {
        const double z2 = (kk - 1.0) * c_w * m.m2 + (kk - 1.0) * (kk - 2.0) * m.m1 * m.m1 +
                          kp * (2.0 * (kk - 1.0) * m.m1 * m.k1 + c_w * m.k1 * m.k1);
        const double m2 = scale * scale * z2 * f / ((kk - 1.0) * (kk - 2.0));
        t.variance = m2 - mean * mean;
        t.mse = t.variance + t.error * t.error;
    }
    return t;
}

EstimatorTheory classic_theory(size_t k, size_t n, double c_w, const KernelMoments& m) {
    return kernel_theory(true, 1.0, k, n, c_w, m);
}
EstimatorTheory corrected_theory(size_t k, size_t n, double c_w, const KernelMoments& m) {
    return kernel_theory(false, 1.0, k, n, c_w, m);
}
EstimatorTheory mse_optimal_theory(size_t k, size_t n, double c_w, const KernelMoments& m) {
    const double kk = double(k);
    if (m.constant) return kernel_theory(false, (kk - 2.0) / (kk - 1.0), k, n, c_w, m);
    return kernel_theory(false, (kk - 2.0) / (kk - 2.0 + m.variance_factor()), k, n, c_w, m);
}

// The registry: one line per estimator.
const EstimatorEntry kEstimators[] = {
    {"classic", "sum_{i=1..k} w_i / V(r_k), bias +1/(k-1)", 2, estimate_classic<double>, estimate_classic<Rgb>,
     classic_theory, [](size_t k) { return double(k); }, {true, true, false, nullptr, nullptr}},
    {"corrected", "sum_{i=1..k-1} w_i / V(r_k), unbiased", 2, estimate_corrected<double>, estimate_corrected<Rgb>,
     corrected_theory, [](size_t k) { return double(k) - 1.0; },
     {false, true, true, "it drops the k-th photon",
      "is unbiased but has infinite variance (relative variance 1/(k-2)); use k >= 3"}},
    {"mse_optimal", "(k-2)/(k-1) sum_{i=1..k-1} w_i / V(r_k), bias -1/(k-1)", 3, estimate_mse_optimal<double>,
     estimate_mse_optimal<Rgb>, mse_optimal_theory, [](size_t k) { return double(k) - 2.0; }, {}},
};

}  // namespace

const std::vector<Estimator>& Estimator::all() {
    static const std::vector<Estimator> list = [] {
        std::vector<Estimator> l;
        for (const EstimatorEntry& e : kEstimators) l.push_back(Estimator(&e));
        return l;
    }();
    return list;
}

std::vector<std::string> Estimator::names() { return registry_names(kEstimators); }

Estimator Estimator::named(const std::string& name) {
    if (const EstimatorEntry* e = registry_find(kEstimators, name)) return Estimator(e);
    throw Error("estimator: unknown value '" + name + "' (allowed: " + registry_list(names()) + ")");
}

std::string Estimator::label() const {
    if (kernel_.is_constant()) return name();
    return std::string(name()) + "/" + kernel_.label();
}

EstimatorTheory Estimator::uniform_theory(size_t k, size_t n, double c_w, int dim) const {
    if (!entry_->uniform_theory) throw Error(std::string("estimator ") + name() + " has no uniform theory");
    return entry_->uniform_theory(k, n, c_w, kernel_.moments(dim));
}

void Estimator::validate_k(size_t k) const {
    if (k < min_k())
        throw Error(std::string("estimator ") + name() + ": k = " + std::to_string(k) +
                    " is out of range (allowed: k >= " + std::to_string(min_k()) + ")");
}

std::string Estimator::warning(size_t k) const {
    if (traits().min_k_warning && k == min_k())
        return std::string("estimator ") + name() + " with k = " + std::to_string(k) + " " + traits().min_k_warning;
    return {};
}

double ball_volume(int dim, double r) {
    if (dim == 2) return kPi * r * r;
    if (dim == 3) return (4.0 / 3.0) * kPi * r * r * r;
    throw Error("ball_volume: dimension " + std::to_string(dim) + " is out of range (allowed: 2, 3)");
}

const char* estimate_case_name(EstimateCase c) {
    switch (c) {
        case EstimateCase::knn: return "knn";
        case EstimateCase::fixed_radius: return "fixed_radius";
        case EstimateCase::all_photons: return "all_photons";
        case EstimateCase::insufficient: return "insufficient";
        case EstimateCase::extended: return "extended";
        case EstimateCase::degenerate: return "degenerate";
        case EstimateCase::empty: return "empty";
        case EstimateCase::need_more: return "need_more";
    }
    return "unknown";
}

void EstimatorStats::count(EstimateCase c) {
    ++queries;
    switch (c) {
        case EstimateCase::knn: ++knn; break;
        case EstimateCase::fixed_radius: ++fixed_radius; break;
        case EstimateCase::all_photons: ++all_photons; break;
        case EstimateCase::insufficient: ++insufficient; break;
        case EstimateCase::extended: ++extended; break;
        case EstimateCase::degenerate: ++degenerate; break;
        case EstimateCase::empty: ++empty; break;
        case EstimateCase::need_more: --queries; break;
    }
}

void EstimatorStats::merge(const EstimatorStats& o) {
    queries += o.queries;
    knn += o.knn;
    fixed_radius += o.fixed_radius;
    all_photons += o.all_photons;
    insufficient += o.insufficient;
    extended += o.extended;
    degenerate += o.degenerate;
    empty += o.empty;
}

std::vector<std::pair<std::string, uint64_t>> EstimatorStats::fields() const {
    return {{"queries", queries},         {"knn", knn},           {"fixed_radius", fixed_radius},
            {"all_photons", all_photons}, {"insufficient", insufficient}, {"extended", extended},
            {"degenerate", degenerate},   {"empty", empty}};
}

std::string EstimatorStats::to_string() const {
    std::ostringstream s;
    for (const auto& [name, count] : fields()) s << (name == "queries" ? "" : " ") << name << "=" << count;
    return s.str();
}

namespace {

// Gathers the k nearest photons, weights each with weight(neighbour) and applies the estimator
// in `dim` dimensions; doubles the gather while rule (c) needs more neighbours than it has.
template <class Weight>
Estimate<Rgb> gather_and_estimate(const PhotonMap& map, const Vec3& x, Estimator e, size_t k, double max_radius,
                                  int dim, GatherBuffers& buf, EstimatorStats* stats, const Weight& weight,
                                  size_t gather = 0) {
    e.validate_k(k);
    size_t want = std::max(k, gather);
    for (;;) {
        // Rule (b) with the whole map as the neighbourhood: one linear pass, the farthest last
        // (a kd-tree query for k >= n would cost O(n log n) or worse per estimate).
        const bool whole_map = want >= map.size() && !std::isfinite(max_radius);
        const size_t found = whole_map ? map.gather_all(x, buf.list) : map.knn(x, want, max_radius, buf.list);
        const bool complete = whole_map || found < want || found == map.size();
        if (buf.w.size() < found) {
            buf.w.resize(found);
            buf.d2.resize(found);
        }
        for (size_t i = 0; i < found; ++i) {
            buf.w[i] = weight(buf.list[i]);
            buf.d2[i] = buf.list[i].d2;
        }
        Estimate<Rgb> est = estimate_density<Rgb>(e, buf.w.data(), buf.d2.data(), found, complete, k, max_radius,
                                                  dim, stats, map.position_resolution());
        if (est.kind != EstimateCase::need_more) return est;
        want *= 2;   // rule (c): coincident photons fill the list, gather more
    }
}

}  // namespace

Estimate<Rgb> estimate_in_scattering(const PhotonMap& map, const Vec3& x, const Vec3& w_o, double g,
                                     Estimator e, size_t k, double max_radius, GatherBuffers& buf,
                                     EstimatorStats* stats, size_t gather) {
    return gather_and_estimate(
        map, x, e, k, max_radius, 3, buf, stats, [&](const Neighbour& n) -> Rgb { return hg_eval(n.direction.dot(w_o), g) * n.power; },
        gather);
}

Estimate<Rgb> estimate_surface_irradiance(const PhotonMap& map, const Vec3& x, const Vec3& n, Estimator e,
                                          size_t k, double max_radius, GatherBuffers& buf, EstimatorStats* stats) {
    // Photons that arrived from the other side of the surface weigh zero (no light through walls).
    return gather_and_estimate(map, x, e, k, max_radius, 2, buf, stats, [&](const Neighbour& nb) -> Rgb {
        return nb.direction.dot(n) < 0.0 ? nb.power : Rgb::Zero();
    });
}

}  // namespace vpm
