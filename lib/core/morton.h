#pragma once
// Morton (Z-order) codes of points in a box, 21 bits per axis: the photon map's storage order
// (photon/map/photon_map.h) and the octree cells of photon/map/photon_cell_counts.h, where the photons of
// one cell at level l share the code's top 3 l bits.
#include <algorithm>
#include <cstdint>

#include "core/math.h"

namespace vpm {

constexpr int kMortonBits = 21;   // per axis

// Spreads the low 21 bits of v to every third bit.
inline uint64_t spread_bits(uint64_t v) {
    v &= 0x1fffff;
    v = (v | v << 32) & 0x1f00000000ffffULL;
    v = (v | v << 16) & 0x1f0000ff0000ffULL;
    v = (v | v << 8) & 0x100f00f00f00f00fULL;
    v = (v | v << 4) & 0x10c30c30c30c30c3ULL;
    v = (v | v << 2) & 0x1249249249249249ULL;
    return v;
}

// Grid steps per box side: coordinate t in [0, 1] of the box falls in step floor(t * kMortonScale),
// so a cell of 2^b steps spans 2^b / kMortonScale of the side (the far face in the last step).
constexpr double kMortonScale = double((1u << kMortonBits) - 1);

// The code of x in the box [lo, lo + extent] (extent > 0 on every axis), each coordinate clamped into it.
inline uint64_t morton_code(const Vec3& x, const Vec3& lo, const Vec3& extent) {
    uint64_t code = 0;
    for (int a = 0; a < 3; ++a) {
        const double t = std::min(std::max((x[a] - lo[a]) / extent[a], 0.0), 1.0);
        code |= spread_bits(static_cast<uint64_t>(t * kMortonScale)) << a;
    }
    return code;
}

}  // namespace vpm
