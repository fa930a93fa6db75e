#pragma once
// Per-photon radii for sample-point (variable-kernel) estimates such as the beam radiance
// estimate (Jarosz, Zwicker & Jensen 2008): photon i gets r_i, the distance to its k-th nearest
// *other* photon. The photon does not count itself: by Slivnyak's theorem the other photons of a
// Poisson process seen from one of its points are again Poisson with the same density, so r_i is
// then independent of where the estimate is evaluated, which is what makes the estimate unbiased
// for every k with a normalised kernel (docs/beam_estimate.md).
#include <cstddef>
#include <vector>

#include "photon/map/photon_map.h"

namespace vpm {

// r_i for every stored photon (stored order), computed in parallel; deterministic (each radius
// depends only on the map). A map with k or fewer photons has no k-th other photon: every radius
// is kInfinity then, and callers must fall back (the point estimates' starved-map rule).
std::vector<double> photon_radii(const PhotonMap& map, size_t k);

}  // namespace vpm
