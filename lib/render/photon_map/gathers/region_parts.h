#pragma once
// A segment gather's structures per glass region (scene/dielectric_regions.h): one Part per region
// that has discs or beams, in ascending region order, or a single Part for the whole map where the
// scene has no closed glass shape. A Part has a `region` and a `bvh` with size().
#include <algorithm>
#include <vector>

#include "scene/dielectric_regions.h"

namespace vpm {

// Whether any part has something to query.
template <class Part>
bool any_part_built(const std::vector<Part>& parts) {
    return std::any_of(parts.begin(), parts.end(), [](const Part& p) { return p.bvh.size() > 0; });
}

// The part of `region` (the only one when not split); null where that region has none.
template <class Part>
const Part* part_of_region(const std::vector<Part>& parts, bool split, RegionMask region) {
    if (!split) return &parts.front();
    const auto it = std::lower_bound(parts.begin(), parts.end(), region, [](const Part& p, RegionMask r) { return p.region < r; });
    return it != parts.end() && it->region == region ? &*it : nullptr;
}

}  // namespace vpm
