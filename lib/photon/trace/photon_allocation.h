#pragma once
// How many photons each light emits (photons.allocation: photons where they can matter).
//
// "power" (the classic rule): light l emits a share of the photons proportional to its power.
// "importance" (default): a short pilot measures how much of each light's stored photon power lands
// where the camera looks, and the photons are shared by that, mixed with the power shares:
//
//     w_l = (1 - kPowerMix) I_l / sum I + kPowerMix P_l / sum P,      kPowerMix = 0.1
//
// I_l = the stored power of a pilot of kPilotPhotons photons of light l alone that lands in the
// region the camera sees: within h_q of a camera point q, h_q the distance from q to its kPilotK-th
// nearest camera point (the points' own spacing). The camera points are the first medium collision
// or surface hit of kPilotRays camera rays through random pixels (stored photons are what the
// camera path's estimates gather there). The mixture keeps every light with power above 10% of its
// power share, so a light the pilot missed still has photons, and the photon tracer divides each photon's power by its pick
// probability: the map is unbiased for any such weights. What changes is where photons go: in a
// scene whose environment light pours nearly all the power into the far skin of a large medium
// while the camera looks at a point light's neighbourhood inside it, power shares give the point
// light a few photons (an image 3000x too dark at 1e5 photons), importance gives it ~90%.
// Falls back to the power shares when the pilot sees nothing (no camera point, or no photon near one).
#include <cstdint>
#include <string>
#include <vector>

#include "photon/trace/photon_tracer.h"
#include "scene/scene.h"

namespace vpm {

struct LightAllocation {
    std::vector<double> weights;      // pick probabilities, one per light (sum 1)
    std::vector<double> power_share;  // P_l / sum P
    std::vector<double> importance;   // I_l / sum I (zeros when the pilot saw nothing)
    uint64_t pilot_photons = 0, pilot_camera_points = 0;
    bool from_pilot = false;          // false: power shares (allocation "power" or nothing seen)
    std::string to_string() const;
};

constexpr double kPowerMix = 0.1;
constexpr uint64_t kPilotPhotons = 4096;
constexpr int kPilotRays = 1024;
constexpr size_t kPilotK = 8;

// The power shares (allocation "power").
LightAllocation power_allocation(const Scene& scene);
// The pilot above; `base` gives seed, storage rules and bounces (its count and weights are ignored).
LightAllocation importance_allocation(const Scene& scene, const PhotonTraceSettings& base);

}  // namespace vpm
