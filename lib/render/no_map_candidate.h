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
namespace vpm {

constexpr const char* kNoMapCandidate = "continue";

}  // namespace vpm
