#include "render/photon_map/photon_lights_report.h"

#include <ostream>

namespace vpm {

void report_photon_lights(const Scene& scene, const char* allocation_rule, const LightAllocation& allocation,
                          const PhotonTraceResult& traced, PhotonPassStats& stats, std::ostream* log) {
    const double stored = double(traced.photons.size() + traced.surface_photons.size());
    stats.allocation = allocation_rule;
    stats.stored_per_emitted = traced.paths ? stored / double(traced.paths) : 0.0;
    if (log)
        *log << "photons: " << stored << " stored per " << traced.paths << " emitted (" << stats.stored_per_emitted
             << " per photon); allocation " << allocation_rule << ": " << allocation.to_string() << "\n";
    if (log)
        for (const std::string& line : scene.prepare_photon_emission()) *log << "photons: " << line << "\n";
    stats.lights.clear();
    for (size_t l = 0; l < scene.lights.size(); ++l) {
        LightPhotonReport r;
        r.light = scene.lights[l]->describe();
        r.weight = l < allocation.weights.size() ? allocation.weights[l] : 0.0;
        r.power_share = l < allocation.power_share.size() ? allocation.power_share[l] : 0.0;
        r.importance = l < allocation.importance.size() ? allocation.importance[l] : 0.0;
        if (l < traced.per_light.size()) r.counts = traced.per_light[l];
        const double landed = r.counts.emitted ? double(r.counts.landed) / double(r.counts.emitted) : 0.0;
        r.wasted = r.counts.emitted > 0 && landed < kWastedLightFraction;
        r.reaches_nothing = !(luminance(scene.lights[l]->power()) > 0.0);
        if (log) {
            *log << "photons: light " << l << " (" << r.light << "): " << r.counts.emitted << " emitted, "
                 << r.counts.landed << " reached the scene, " << r.counts.stored << " stored\n";
            if (r.reaches_nothing)
                *log << "warning: light " << l << " (" << r.light << "): its power towards the scene's media and "
                        "shapes is zero (it emits nothing, or none of its light can reach them); it emits no photons\n";
            if (r.wasted)
                *log << "warning: light " << l << " (" << r.light << "): " << 100.0 * (1.0 - landed)
                     << "% of its photons reach nothing (no medium collision, no surface); they cost time and "
                        "add nothing\n";
        }
        stats.lights.push_back(r);
    }
}

}  // namespace vpm
