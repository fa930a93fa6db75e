#include "photon/estimators.h"

#include <sstream>

#include "core/henyey_greenstein.h"

namespace vpm {

const char* estimator_name(Estimator e) {
    switch (e) {
        case Estimator::classic: return "classic";
        case Estimator::corrected: return "corrected";
        case Estimator::mse_optimal: return "mse_optimal";
    }
    return "unknown";
}

Estimator parse_estimator(const std::string& name) {
    for (Estimator e : kAllEstimators)
        if (name == estimator_name(e)) return e;
    throw Error("estimator: unknown value '" + name + "' (allowed: classic, corrected, mse_optimal)");
}

size_t estimator_min_k(Estimator e) {
    switch (e) {
        case Estimator::classic: return 1;
        case Estimator::corrected: return 2;
        case Estimator::mse_optimal: return 3;
    }
    return 1;
}

void validate_estimator_k(Estimator e, size_t k) {
    if (k < estimator_min_k(e))
        throw Error(std::string("estimator ") + estimator_name(e) + ": k = " + std::to_string(k) +
                    " is out of range (allowed: k >= " + std::to_string(estimator_min_k(e)) + ")");
}

std::string estimator_warning(Estimator e, size_t k) {
    if (e == Estimator::corrected && k == 2)
        return "estimator corrected with k = 2 is unbiased but has infinite variance "
               "(relative variance 1/(k-2)); use k >= 3";
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
                                  int dim, GatherBuffers& buf, EstimatorStats* stats, const Weight& weight) {
    validate_estimator_k(e, k);
    size_t want = k;
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
                                     EstimatorStats* stats) {
    return gather_and_estimate(map, x, e, k, max_radius, 3, buf, stats,
                               [&](const Neighbour& n) -> Rgb { return hg_eval(n.direction.dot(w_o), g) * n.power; });
}

Estimate<Rgb> estimate_surface_irradiance(const PhotonMap& map, const Vec3& x, const Vec3& n, Estimator e,
                                          size_t k, double max_radius, GatherBuffers& buf, EstimatorStats* stats) {
    // Photons that arrived from the other side of the surface weigh zero (no light through walls).
    return gather_and_estimate(map, x, e, k, max_radius, 2, buf, stats, [&](const Neighbour& nb) -> Rgb {
        return nb.direction.dot(n) < 0.0 ? nb.power : Rgb::Zero();
    });
}

}  // namespace vpm
