#pragma once
// One photon map per region (scene/dielectric_regions.h): the photons of each set of glass shapes
// containing them in a kd-tree of their own, so that a query counts only the photons of its own side
// of every glass interface. The photon record (photon.h) is unchanged: the region is the tree's.
#include <vector>

#include "photon/map/photon_map.h"
#include "scene/dielectric_regions.h"

namespace vpm {

class RegionPhotonMaps {
public:
    RegionPhotonMaps() = default;
    // `regions`: one per photon, in its order (photon_tracer.h), and not empty.
    RegionPhotonMaps(const std::vector<PhotonInput>& photons, const std::vector<RegionMask>& regions);

    bool empty() const { return maps_.empty(); }
    size_t regions() const { return maps_.size(); }
    // The map of `region`; an empty map where no photon of it was stored.
    const PhotonMap& at(RegionMask region) const;
    RegionMask region(size_t i) const { return keys_[i]; }
    const PhotonMap& map(size_t i) const { return maps_[i]; }
    size_t size() const;
    size_t memory_bytes() const;

private:
    std::vector<RegionMask> keys_;   // ascending
    std::vector<PhotonMap> maps_;    // by keys_
    PhotonMap none_;
};

}  // namespace vpm
