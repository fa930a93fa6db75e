#pragma once
// Distinct walks in a distance-sorted neighbour list: the walk neighbourhood of
// photon/estimate/walk_estimate.h ends at the first photon of the k-th distinct walk.
#include <cstddef>
#include <cstdint>
#include <vector>

namespace vpm {

// A small open-addressing set of walk ids (PhotonMap::walk ids, < 2^32 - 1) over caller-owned slots,
// so that a query allocates nothing once the slots have grown.
class WalkSet {
public:
    WalkSet(std::vector<uint32_t>& slots, size_t capacity) : slots_(slots) {
        size_t n = 16;
        while (n < 2 * capacity) n *= 2;
        slots_.assign(n, kEmpty);
        mask_ = n - 1;
    }
    // true if walk was not in the set yet
    bool insert(uint32_t walk) {
        size_t h = (size_t(walk) * 0x9E3779B1u) & mask_;
        while (slots_[h] != kEmpty) {
            if (slots_[h] == walk) return false;
            h = (h + 1) & mask_;
        }
        slots_[h] = walk;
        return true;
    }

private:
    static constexpr uint32_t kEmpty = 0xffffffffu;
    std::vector<uint32_t>& slots_;
    size_t mask_ = 0;
};

// The walk neighbourhood of a list of `found` entries sorted by distance, walk_of(i) the walk of
// entry i: returns the number of entries up to and including the first photon of the k-th distinct
// walk, and sets `walks` to k; if the list holds fewer than k walks, returns found and sets `walks`
// to their number.
template <class WalkOf>
size_t walk_neighbourhood_size(size_t found, size_t k, const WalkOf& walk_of, std::vector<uint32_t>& slots, size_t& walks) {
    walks = 0;
    WalkSet seen(slots, found);
    for (size_t i = 0; i < found; ++i)
        if (seen.insert(walk_of(i)) && ++walks == k) return i + 1;
    return found;
}

}  // namespace vpm
