#pragma once
// photons.store_probability = "auto": the storage probability from the photon pass's own walk
// statistics. A walk in a dense, bright medium stores a cluster of collisions a few mean free
// paths across (8.9 per walk in a box at optical thickness 100, albedo 0.99); the kNN estimate
// sees such a cluster as one sample, so most of it costs trace, build and query time for little.
// The pass's first batch (4096 photons, traced alone first: photon_tracer.cpp) stores every
// collision; the rest store each with q = min(1, kAutoStoredPerWalk / m), m that batch's stored
// photons per walk that stored any. Deterministic from counts; unbiased for any q fixed before
// the photons it applies to (power / q).
//
// kAutoStoredPerWalk = 2, measured (docs/studies/photon_tracing.md section 3): in that box q = 0.25 (about 2 per
// walk) gave the least error^2 x time of q = 1, 0.25, 0.0625 (0.186 against 0.426 and 0.651);
// where walks store fewer than 2 (thin media, the default plume) nothing is thinned.
#include <algorithm>
#include <cstdint>

namespace vpm {

constexpr double kAutoStoredPerWalk = 2.0;

inline double auto_store_probability(uint64_t stored, uint64_t storing_walks) {
    if (stored == 0 || storing_walks == 0) return 1.0;
    return std::min(1.0, kAutoStoredPerWalk * double(storing_walks) / double(stored));
}

}  // namespace vpm
