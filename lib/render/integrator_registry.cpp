#include "render/integrator_registry.h"

#include "render/path_tracer.h"
#include "render/photon_map_integrator.h"

namespace vpm {

const std::vector<IntegratorType>& integrator_types() {
    static const std::vector<IntegratorType> types = {
        {"path", "unbiased volumetric path tracer (the reference)", read_path_tracer_settings},
        {"photon_map", "volumetric photon map with a kNN estimator", read_photon_map_settings},
    };
    return types;
}

std::vector<std::string> integrator_names() {
    std::vector<std::string> names;
    for (const IntegratorType& t : integrator_types()) names.push_back(t.name);
    return names;
}

}  // namespace vpm
