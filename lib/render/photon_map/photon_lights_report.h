#pragma once
// Where a photon pass's photons went, per light: fills PhotonPassStats (allocation,
// stored_per_emitted, lights; run_stats.h) and writes the log lines. A light whose photons mostly
// reach nothing (landed / emitted < kWastedLightFraction = 1/4: no medium collision, no surface) is
// marked wasted and gets a warning in the log.
#include <iosfwd>

#include "photon/trace/photon_allocation.h"
#include "photon/trace/photon_tracer.h"
#include "render/photon_map/photon_map_stats.h"
#include "scene/scene.h"

namespace vpm {

constexpr double kWastedLightFraction = 0.25;   // more than 3/4 of its photons reach nothing

void report_photon_lights(const Scene& scene, const char* allocation_rule, const LightAllocation& allocation,
                          const PhotonTraceResult& traced, PhotonPassStats& stats, std::ostream* log);

}  // namespace vpm
