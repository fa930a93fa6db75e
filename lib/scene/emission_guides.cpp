#include "scene/emission_guides.h"

#include <cmath>
#include <memory>
#include <sstream>

#include <tbb/parallel_for.h>

#include "core/sampling/rng.h"
#include "scene/scene.h"

namespace vpm {

namespace {

constexpr uint64_t kGuideSeed = 0x6775696465726179ULL;   // the guide rays' own stream

// Probability that a photon leaving `origin` along w (from distance `start`) meets a medium or a
// surface at first flight.
double reach_probability(const Scene& scene, const Vec3& origin, double start, const Vec3& w) {
    const Ray ray{origin + start * w, w};
    SurfaceHit hit;
    if (scene.surfaces && scene.surfaces->intersect(ray, kInfinity, hit)) return 1.0;
    return -std::expm1(-scene.optical_depth(ray, kInfinity));
}

}  // namespace

EmissionGuideEstimate estimate_emission_guide(const Scene& scene, size_t index, std::vector<double>& weights) {
    const Light& light = *scene.lights[index];
    EmissionGuideEstimate e;
    weights.assign(size_t(DirectionGuide::kColumns) * DirectionGuide::kRows, 0.0);
    Vec3 origin;
    double start = 0.0;
    if (!light.guide_origin(origin, start)) return e;
    constexpr int kRays = kGuideRaysPerSide * kGuideRaysPerSide;
    std::vector<double> mean_reach(weights.size(), 0.0);
    tbb::parallel_for(0, int(weights.size()), [&](int cell) {
        const int column = cell % DirectionGuide::kColumns, row = cell / DirectionGuide::kColumns;
        Rng rng(kGuideSeed, uint64_t(index) * weights.size() + uint64_t(cell));
        for (int k = 0; k < kRays; ++k) {
            const double du = (k % kGuideRaysPerSide + rng.uniform()) / kGuideRaysPerSide;
            const double dv = (k / kGuideRaysPerSide + rng.uniform()) / kGuideRaysPerSide;
            const Vec3 w = DirectionGuide::direction(column, row, du, dv);
            const double pdf = light.emission_direction_pdf(w);
            if (!(pdf > 0.0)) continue;
            const double reach = reach_probability(scene, origin, start, w);
            mean_reach[size_t(cell)] += reach / kRays;
            weights[size_t(cell)] += pdf * reach / kRays;
        }
    });
    // Over the light's own directions: the sum of density x reach x solid angle. Over the guide's:
    // each cell's probability (its weight's share) times the mean reach of its directions.
    double reach_own = 0.0, total = 0.0, guided = 0.0;
    for (size_t c = 0; c < weights.size(); ++c) {
        reach_own += weights[c] * DirectionGuide::cell_solid_angle();
        total += weights[c];
        guided += weights[c] * mean_reach[c];
    }
    e.reach_own = reach_own;
    e.reach_mixture = reach_own;
    if (!(total > 0.0)) return e;
    const double reach_guide = guided / total;
    const double mixture = (1.0 - kGuideShare) * reach_own + kGuideShare * reach_guide;
    if (mixture >= kGuideMinGain * reach_own) {
        e.guided = true;
        e.reach_mixture = mixture;
    }
    return e;
}

std::vector<std::string> guide_photon_emission(const Scene& scene) {
    std::vector<std::string> log;
    std::vector<double> weights;
    for (size_t i = 0; i < scene.lights.size(); ++i) {
        const EmissionGuideEstimate e = estimate_emission_guide(scene, i, weights);
        if (!e.guided) continue;
        scene.lights[i]->set_emission_guide(std::make_shared<const DirectionGuide>(weights), kGuideShare);
        std::ostringstream s;
        s.precision(3);
        s << "light " << i << ": " << 100.0 * kGuideShare << "% of its photons follow a guide towards what they can reach "
          << "(scene/emission_guides.h): " << 100.0 * e.reach_mixture << "% expected to meet a medium or a surface at first "
          << "flight instead of " << 100.0 * e.reach_own << "%";
        log.push_back(s.str());
    }
    return log;
}

}  // namespace vpm
