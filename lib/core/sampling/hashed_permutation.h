#pragma once
// Element i of a pseudo-random permutation of [0, n) chosen by a 64-bit key, computed alone (no
// table): a keyed bijection of the w-bit integers (2^w >= n) applied until the value falls below n
// (cycle walking keeps it a bijection of [0, n)), then rotated by a key-chosen offset in [0, n), so
// that over keys each i lands on every value with probability 1/n (to within n / 2^64).
#include <cstdint>

#include "core/sampling/rng.h"

namespace vpm {

inline uint32_t permutation_element(uint32_t i, uint32_t n, uint64_t key) {
    if (n <= 1) return 0;
    int w = 0;
    while ((uint64_t(1) << w) < n) ++w;
    const uint32_t mask = uint32_t((uint64_t(1) << w) - 1);
    const int shift = (w + 1) / 2;
    uint64_t k[4];
    for (int r = 0; r < 4; ++r) k[r] = mix64(key + uint64_t(r) * 0x632be59bd9b4e019ULL);
    do {
        for (int r = 0; r < 4; ++r) {   // each step a bijection of the w-bit integers
            i = (i ^ uint32_t(k[r])) & mask;
            i = (i * (uint32_t(k[r] >> 32) | 1u)) & mask;
            i ^= i >> shift;
        }
    } while (i >= n);
    const uint64_t offset = mix64(key ^ 0x726f74617465ULL) % n;
    return uint32_t((uint64_t(i) + offset) % n);
}

}  // namespace vpm
