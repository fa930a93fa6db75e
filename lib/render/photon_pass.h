#pragma once
// The photon-map integrator's pass before the camera pass: trace the photons, then build the
// kd-trees (the volume map, and the surface map when asked), recording phases "trace",
// "build_surface" and "build", the energy balance, counts and memory in RunStats, and one log
// line each. Before building, a map projected over the memory budget is announced.
#include <optional>

#include "photon/photon_allocation.h"
#include "photon/photon_map.h"
#include "render/integrator.h"
#include "photon/photon_map_settings.h"
#include "render/run_stats.h"
#include "scene/scene.h"

namespace vpm {

struct PhotonMaps {
    PhotonMap volume;
    PhotonMap surface;   // empty unless built
};

// `allocation`: photons per light; computed on the first call (a pilot, for "importance") and
// reused by later passes of the run. The pilot's streams depend on the run's stream offset, not on
// the pass, so every pass (and every machine rendering passes of the same run) shares it.
PhotonMaps run_photon_pass(const Scene& scene, const PhotonMapSettings& settings, const PassContext& context,
                           bool surface_map, RunStats& stats, std::optional<LightAllocation>& allocation);

}  // namespace vpm
