#include "photon/map/region_photon_maps.h"

#include <algorithm>
#include <map>

#include "core/error.h"

namespace vpm {

RegionPhotonMaps::RegionPhotonMaps(const std::vector<PhotonInput>& photons, const std::vector<RegionMask>& regions) {
    if (regions.size() != photons.size())
        throw Error("region photon maps: " + std::to_string(regions.size()) + " regions for " +
                    std::to_string(photons.size()) + " photons");
    std::map<RegionMask, std::vector<PhotonInput>> split;   // photons keep their order within a region
    for (size_t i = 0; i < photons.size(); ++i) split[regions[i]].push_back(photons[i]);
    for (auto& [key, list] : split) {
        keys_.push_back(key);
        maps_.emplace_back(list);
        std::vector<PhotonInput>().swap(list);
    }
}

const PhotonMap& RegionPhotonMaps::at(RegionMask region) const {
    const auto it = std::lower_bound(keys_.begin(), keys_.end(), region);
    return it != keys_.end() && *it == region ? maps_[size_t(it - keys_.begin())] : none_;
}

size_t RegionPhotonMaps::size() const {
    size_t n = 0;
    for (const PhotonMap& m : maps_) n += m.size();
    return n;
}

size_t RegionPhotonMaps::memory_bytes() const {
    size_t n = 0;
    for (const PhotonMap& m : maps_) n += m.memory_bytes();
    return n;
}

}  // namespace vpm
