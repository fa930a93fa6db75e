#pragma once
// Nested uniform scrambling (Owen 1995) of a binary fraction, with the tree's random flips drawn
// from a hash of (seed, node) instead of stored. Bit b (counted from the top) is flipped by a fair
// coin that belongs to the node of the b bits above it, so every output is uniform in [0, 1)
// while a (t, m, s)-net stays one (the scramble maps elementary intervals onto elementary intervals).
//
// A set of at most 2^depth points whose top `depth` bits differ (the first 2^depth points of a
// Sobol' dimension) has one point per node below that depth: the flips there are independent fair
// coins, so the bits below are fresh random bits. This draws them as such: the same law as
// scrambling all the digits, with `depth` hashes per value instead of 53.
#include <cstdint>

#include "core/sampling/rng.h"

namespace vpm {

// Smallest depth with 2^depth >= n (0 for n <= 1).
inline int scramble_depth(uint64_t n) {
    int depth = 0;
    while (depth < 64 && (uint64_t(1) << depth) < n) ++depth;
    return depth;
}

// The scrambled value of the fraction `bits` (bit 31 = 1/2) as a double in [0, 1) with 53 bits;
// depth <= 32.
inline double owen_scrambled_uniform(uint32_t bits, uint64_t seed, int depth) {
    constexpr uint64_t kNodeSpread = 0x9e3779b97f4a7c15ULL;   // odd: node ids stay distinct
    uint64_t top = 0;   // the scrambled top `depth` bits
    for (int b = 0; b < depth; ++b) {
        const uint64_t prefix = b ? uint64_t(bits >> (32 - b)) : 0;
        const uint64_t node = (uint64_t(1) << b) | prefix;   // heap numbering: unique over (b, prefix)
        const uint64_t flip = mix64(seed ^ (node * kNodeSpread)) >> 63;
        top = (top << 1) | (((bits >> (31 - b)) & 1u) ^ flip);
    }
    const uint64_t leaf = (uint64_t(1) << depth) | (depth ? uint64_t(bits >> (32 - depth)) : 0);
    const uint64_t low = mix64(seed ^ (leaf * kNodeSpread) ^ 0x6c6f77626974ULL);   // the point's own bits
    const uint64_t value = depth ? (top << (53 - depth)) | (low >> (11 + depth)) : low >> 11;
    return double(value) * 0x1.0p-53;
}

}  // namespace vpm
