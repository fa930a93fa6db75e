// The integrator registry's readers of "photon_map" and "auto" (render/integrator_registry.cpp).
#include "config/params.h"
#include "render/photon_map/photon_map_integrator.h"

namespace vpm {

namespace {

struct PhotonMapIntegratorSettings : IntegratorSettings {
    PhotonMapSettings settings;
    std::unique_ptr<Integrator> create(const Scene& scene) const override {
        return std::make_unique<PhotonMapIntegrator>(scene, settings);
    }
};

}  // namespace

std::unique_ptr<IntegratorSettings> read_photon_map_settings(Params& render, Params& root) {
    auto s = std::make_unique<PhotonMapIntegratorSettings>();
    Params photons = root.table("photons");
    s->settings = PhotonMapSettings::read(render, photons);
    photons.finish();
    return s;
}

std::unique_ptr<IntegratorSettings> read_auto_integrator_settings(Params& render, Params& root) {
    auto s = std::make_unique<PhotonMapIntegratorSettings>();
    Params photons = root.table("photons");
    s->settings = PhotonMapSettings::read(render, photons, true);
    photons.finish();
    // The plan chooses between the path tracer and the gathers its pilot measures: a gather that is
    // chosen otherwise cannot be honoured with it.
    const GatherMode g = s->settings.gather;
    if (render.string("integrator", "path") == "auto" && g != GatherMode::automatic && !gather_entry(g).plan_measures) {
        std::string allowed = "\"auto\"";
        for (const GatherEntry& e : gather_entries())
            if (e.plan_measures) allowed += std::string(", \"") + e.name + "\"";
        photons.fail("gather", "render.integrator = \"auto\" chooses between the path tracer and the photon map's "
                               "gathers its pilot measures: photons.gather must be " + allowed +
                               " with it (or set render.integrator = \"photon_map\")");
    }
    return s;
}

const PhotonMapSettings& photon_map_settings(const RunConfig& config) {
    return static_cast<const PhotonMapIntegratorSettings&>(config.settings_for("photon_map")).settings;
}

}  // namespace vpm
