#include "photon/estimate/walk_estimate.h"

#include <algorithm>

#include "core/error.h"
#include "core/henyey_greenstein.h"

namespace vpm {

const char* neighbourhood_name(Neighbourhood n) { return n == Neighbourhood::walks ? "walks" : "photons"; }

const std::vector<std::string>& neighbourhood_names() {
    static const std::vector<std::string> names = {"photons", "walks"};
    return names;
}

Neighbourhood parse_neighbourhood(const std::string& value, const std::string& key) {
    if (value == "photons") return Neighbourhood::photons;
    if (value == "walks") return Neighbourhood::walks;
    throw Error(key + " = \"" + value + "\" is not allowed (allowed: \"photons\", \"walks\")");
}

void validate_walk_estimator(const Estimator& e) {
    const std::string name = e.name();
    if (name != "classic" && name != "corrected")
        throw Error("photons.neighbours = \"walks\": estimator \"" + name +
                    "\" has no walk form (allowed: \"classic\", \"corrected\")");
}

namespace {

// Gathers the walk neighbourhood of k walks, weights each photon with weight(neighbour) and applies
// the estimator in `dim` dimensions; doubles the walks gathered while rule (c) needs more list.
template <class Weight>
Estimate<Rgb> gather_walks_and_estimate(const PhotonMap& map, const Vec3& x, const Estimator& e, size_t k,
                                        double max_radius, int dim, GatherBuffers& buf, EstimatorStats* stats,
                                        const Weight& weight) {
    validate_walk_estimator(e);
    e.validate_k(k);
    size_t want = k;
    for (;;) {
        size_t walks = 0;
        const size_t found = map.knn_walks(x, want, max_radius, buf.list, walks);
        const bool complete = walks < want;
        if (buf.w.size() < found) {
            buf.w.resize(found);
            buf.d2.resize(found);
        }
        for (size_t i = 0; i < found; ++i) {
            buf.w[i] = weight(buf.list[i]);
            buf.d2[i] = buf.list[i].d2;
        }
        Estimate<Rgb> est = estimate_density_walks<Rgb>(
            e, buf.w.data(), buf.d2.data(), found, [&](size_t i) { return buf.list[i].walk; }, complete, k, max_radius,
            dim, buf.list.scratch_set, stats, map.position_resolution());
        if (est.kind != EstimateCase::need_more) return est;
        want *= 2;   // rule (c): coincident photons end the list, gather more walks
    }
}

}  // namespace

Estimate<Rgb> estimate_in_scattering_walks(const PhotonMap& map, const Vec3& x, const Vec3& w_o, double g, Estimator e,
                                           size_t k, double max_radius, GatherBuffers& buf, EstimatorStats* stats) {
    return gather_walks_and_estimate(map, x, e, k, max_radius, 3, buf, stats, [&](const Neighbour& n) -> Rgb {
        return hg_eval(n.direction.dot(w_o), g) * n.power;
    });
}

Estimate<Rgb> estimate_surface_irradiance_walks(const PhotonMap& map, const Vec3& x, const Vec3& n, Estimator e,
                                                size_t k, double max_radius, GatherBuffers& buf,
                                                EstimatorStats* stats) {
    return gather_walks_and_estimate(map, x, e, k, max_radius, 2, buf, stats, [&](const Neighbour& nb) -> Rgb {
        return nb.direction.dot(n) < 0.0 ? nb.power : Rgb::Zero();
    });
}

}  // namespace vpm
