#include "render/photon_lights_report.h"

#include <nlohmann/json.hpp>
#include <ostream>

namespace vpm {

void report_photon_lights(const Scene& scene, const LightAllocation& allocation, const PhotonTraceResult& traced,
                          RunRecord& record, std::ostream* log) {
    const double stored = double(traced.photons.size() + traced.surface_photons.size());
    const double per_emitted = traced.paths ? stored / double(traced.paths) : 0.0;
    record.set("photons.allocation", scene.photons.allocation);
    record.set("photons.stored_per_emitted", per_emitted);
    if (log)
        *log << "photons: " << stored << " stored per " << traced.paths << " emitted (" << per_emitted
             << " per photon); allocation " << scene.photons.allocation << ": " << allocation.to_string() << "\n";
    nlohmann::json lights = nlohmann::json::array();
    for (size_t l = 0; l < scene.lights.size(); ++l) {
        const LightPhotonStats s = l < traced.per_light.size() ? traced.per_light[l] : LightPhotonStats{};
        const double landed = s.emitted ? double(s.landed) / double(s.emitted) : 0.0;
        const double spe = s.emitted ? double(s.stored) / double(s.emitted) : 0.0;
        const bool wasted = s.emitted > 0 && landed < kWastedLightFraction;
        nlohmann::json j;
        j["light"] = scene.lights[l]->describe();
        j["weight"] = l < allocation.weights.size() ? allocation.weights[l] : 0.0;
        j["power_share"] = l < allocation.power_share.size() ? allocation.power_share[l] : 0.0;
        j["importance"] = l < allocation.importance.size() ? allocation.importance[l] : 0.0;
        j["emitted"] = s.emitted;
        j["landed"] = s.landed;
        j["stored"] = s.stored;
        j["stored_per_emitted"] = spe;
        j["landed_fraction"] = landed;
        j["wasted"] = wasted;
        lights.push_back(j);
        if (log) {
            *log << "photons: light " << l << " (" << scene.lights[l]->describe() << "): " << s.emitted << " emitted, "
                 << s.landed << " reached the scene, " << s.stored << " stored\n";
            if (wasted)
                *log << "warning: light " << l << " (" << scene.lights[l]->describe() << "): " << 100.0 * (1.0 - landed)
                     << "% of its photons reach nothing (no medium collision, no surface); they cost time and "
                        "add nothing\n";
        }
    }
    record.set("photons.lights", lights);
}

}  // namespace vpm
