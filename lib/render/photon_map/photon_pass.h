#pragma once
// The photon-map integrator's pass before the camera pass: trace the photons, then build the
// kd-trees (the volume map, and the surface map when asked), recording phases "trace",
// "build_surface" and "build", the energy balance, counts and memory in RunStats, and one log
// line each. Before building, a map projected over the memory budget is announced.
#include <optional>

#include "photon/trace/photon_allocation.h"
#include "photon/map/photon_beam.h"
#include "photon/map/photon_map.h"
#include "photon/map/region_photon_maps.h"
#include "render/integrator.h"
#include "render/photon_map/photon_map_settings.h"
#include "render/photon_map/photon_map_stats.h"
#include "render/plan/work_units.h"
#include "scene/scene.h"

namespace vpm {

struct PhotonMaps {
    PhotonMap volume;
    PhotonMap surface;   // empty unless built
    std::vector<PhotonBeam> beams;   // photons.gather = "photon_beams": the free flights (no volume photons then)
    // A scene with closed glass shapes (scene/dielectric_regions.h): the same photons again, one
    // kd-tree per region, which the estimates query (the maps above serve the rest).
    RegionPhotonMaps volume_regions, surface_regions;
    std::vector<RegionMask> beam_regions;   // the region of each of `beams` (empty without glass shapes)
};

// `allocation`: photons per light; computed on the first call (a pilot, for "importance") and
// reused by later passes of the run. The pilot's streams depend on the run's stream offset, not on
// the pass, so every pass (and every machine rendering passes of the same run) shares it.
PhotonMaps run_photon_pass(const Scene& scene, const PhotonMapSettings& settings, const PassContext& context,
                           bool surface_map, RunStats& stats, std::optional<LightAllocation>& allocation);

// The auto plan's pilot map where photons.count is not given (render/photon_map/auto_gather.cpp): photons.count
// photons, or fewer where walks store many photons each, so that it holds about kPilotStoredPhotons
// (in a dense, bright medium a walk stores tens of photons, and tracing and building the full map
// could take most of a short budget before the pilot finds that no map pays there). A probe of
// one batch, with a seed of its own, measures the volume photons stored per emitted one; the map is traced
// apart from it, as a count chosen on the photons it then normalises would bias them. Under
// render.time_limit its photon pass also counts at most kPilotBudgetFraction of the limit's work
// units (render/plan/pilot_budget.h) where that share holds the probe's photons, so that the first pass can fit.
constexpr double kPilotStoredPhotons = 262144.0;
constexpr int64_t kPilotProbePhotons = 4096;
struct PilotPhotonCount {
    int64_t count = 0;               // the pilot map's photons: a multiple of the probe's, at most photons.count
    int64_t probe_photons = 0;
    double stored_per_photon = 0.0;  // volume photons stored per emitted, in the probe
    double collisions_per_photon = 0.0;   // real medium collisions per emitted, in the probe
    bool held_by_limit = false;      // count was lowered for render.time_limit (not for the stored photons)
};
// Counted work units (render/plan/work_units.h) per emitted photon, from the probe: its walk, collisions and stored photons.
double photon_units(const WorkUnits& w, const PilotPhotonCount& p);
// surface_map: whether the run's passes trace one (the photons per light are computed with it, as
// the passes would, when `allocation` is still empty).
PilotPhotonCount pilot_photon_count(const Scene& scene, const PhotonMapSettings& settings, const PassContext& context,
                                    bool surface_map, std::optional<LightAllocation>& allocation);

}  // namespace vpm
