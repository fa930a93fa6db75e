#pragma once
// T(0, t_i) along one ray for points t_1 <= t_2 <= ... <= t_n, every medium in one walk along its
// majorant pieces: the optical depth itself where the medium is homogeneous (`exact`), ratio
// tracking elsewhere, whose running product over the tentative collisions before t is an unbiased
// estimate of T(0, t) for every t at once. One walk per ray, however many points: the gathers that
// weigh many points of one camera segment (render/photon_map/gathers/photon_beams_gather.h) use it.
#include <cstdint>
#include <vector>

#include "core/math.h"
#include "core/sampling/rng.h"
#include "scene/scene.h"

namespace vpm {

// exact[m]: medium m is homogeneous (its majorant is sigma_t). ts sorted ascending, n > 0.
// out[i] = the estimate of T(0, ts[i]); lookups counts the ratio tracking's sigma_t lookups.
void transmittance_at_points(const Scene& scene, const std::vector<bool>& exact, const Ray& ray, const double* ts,
                             size_t n, double* out, Rng& rng, uint64_t& lookups);

// exact[m] for every medium of the scene.
std::vector<bool> homogeneous_media(const Scene& scene);

}  // namespace vpm
