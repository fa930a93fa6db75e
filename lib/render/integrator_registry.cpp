#include "render/integrator_registry.h"

#include "core/registry.h"

namespace vpm {

// Each integrator's settings reader, defined in its own file.
std::unique_ptr<IntegratorSettings> read_path_tracer_settings(Params& render, Params& root);
std::unique_ptr<IntegratorSettings> read_photon_map_settings(Params& render, Params& root);
std::unique_ptr<IntegratorSettings> read_auto_integrator_settings(Params& render, Params& root);

const std::vector<IntegratorType>& integrator_types() {
    static const std::vector<IntegratorType> types = {
        {"path", "unbiased volumetric path tracer (the reference)", read_path_tracer_settings},
        {"photon_map", "volumetric photon map with a kNN estimator", read_photon_map_settings},
        {"auto", "a pilot chooses the path tracer or the photon map per run, and says which ran", read_auto_integrator_settings},
    };
    return types;
}

std::vector<std::string> integrator_names() { return registry_names(integrator_types()); }

}  // namespace vpm
