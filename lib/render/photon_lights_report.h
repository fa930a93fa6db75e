#pragma once
// Where a photon pass's photons went, per light: the sidecar fields and log lines (issue 12).
//
//   photons.allocation                  "importance" | "power" (photon/photon_allocation.h)
//   photons.stored_per_emitted          (volume + surface records) / photon paths emitted
//   photons.lights[i]                   light, weight (share of photons), power_share, importance,
//                                       emitted, landed (reached a medium collision or a surface),
//                                       stored, stored_per_emitted, landed_fraction
//
// A light whose photons mostly reach nothing (landed_fraction < kWastedLightFraction) gets a
// warning in the log and `wasted = true` in its record.
#include <iosfwd>

#include "photon/photon_allocation.h"
#include "photon/photon_tracer.h"
#include "render/run_record.h"
#include "scene/scene.h"

namespace vpm {

constexpr double kWastedLightFraction = 0.5;

void report_photon_lights(const Scene& scene, const LightAllocation& allocation, const PhotonTraceResult& traced,
                          RunRecord& record, std::ostream* log);

}  // namespace vpm
