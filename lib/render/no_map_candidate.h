#pragma once
// The auto plan's third candidate, "continue": no photon map at all. Every medium collision then
// continues the camera path (next-event estimation and a phase-sampled bounce, as where a kNN ball
// exceeds photons.max_radius_mfp: photon/bounded_radius.h) and surfaces are path traced, so the
// estimate is unbiased and no photon pass is paid for. The pilot measures it like the gathers
// (render/map_noise_pilot.h: an empty map and no surface map, one trace per sample since it has no
// map noise), the plan costs it without the photon pass (render/pass_plan.h), and where it wins the
// passes after the pilot's skip the photon pass (PhotonMapIntegrator::prepare); the pilot's own pass
// renders without its map too, so the whole image is the unbiased continuation.
// Where every kNN ball is wider than max_radius_mfp (matrix v3's dense boxes, BENCHMARKS.md section
// 11.7) the map is never used: the collision gather's samples are then exactly the continuation's,
// and the photon pass (6000-21000 work units per photon) is what decides. The pilot also counts the
// estimates that used a map per sample (CountedOperations::map_used), reported in the log and sidecar.
//
// "continue" is only a choice where the map is next to unused: at most kNoMapMaxUsedShare of the
// map candidates' kNN queries gave an estimate that was used. Scored freely it won in 25 of 56
// matrix cells where the map was used (BENCHMARKS.md section 11.8), the default scene among them,
// and in the box at optical thickness 100 and albedo 0.99 it won on 512 pilot samples that do not
// see the continued paths' heavy tail (2.27x the best forced gather): a photon-map integrator that
// quietly path traces wherever the pilot is unsure is not the photon map a user asked for.
// The pilot is sure where the continued paths are short: at most kNoMapShortPathRays tracked
// segments per sample (free flights and shadow rays; one scattering event at most on average)
// leave no long-path tail for its samples to miss, and there "continue" competes freely. Under a
// sky (sphere and blob at thickness 1: 1.1-1.5 segments per sample) a kNN estimate costs 15-50
// continued samples at the same or lower variance (BENCHMARKS.md section 11.11), while the dense
// boxes the rule was made for continue over 10-19 segments per sample.
#include <algorithm>
#include <vector>

#include "render/pass_plan.h"

namespace vpm {

constexpr const char* kNoMapCandidate = "continue";
constexpr double kNoMapMaxUsedShare = 0.02;
constexpr double kNoMapShortPathRays = 2.0;

// Marks the no-map candidates excluded unless every map candidate used the map in at most
// kNoMapMaxUsedShare of its queries (queries 0: unused), or their own paths are short (at most
// kNoMapShortPathRays tracked segments per sample).
inline void exclude_no_map_where_the_map_is_used(std::vector<GatherMeasurement>& candidates) {
    double share = 0.0;
    for (const GatherMeasurement& m : candidates)
        if (m.uses_map && m.per_sample.queries > 0.0) share = std::max(share, m.per_sample.map_used / m.per_sample.queries);
    if (share <= kNoMapMaxUsedShare) return;
    for (GatherMeasurement& m : candidates)
        if (!m.uses_map && m.per_sample.rays > kNoMapShortPathRays) m.excluded = true;
}

}  // namespace vpm
