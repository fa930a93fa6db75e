#pragma once
// The radius bound's decision map of a run (photon/estimate/bounded_radius.h): the map
// photons.max_radius_mfp's switch is decided on, apart from the maps it selects. A photon-map run
// traces it once, with a seed of its own at photons.count / kShare photons, so every pass and machine
// of the run decides alike; maps built elsewhere give theirs with its ratio.
#include <cstdint>
#include <utility>

#include "photon/map/photon_cell_counts.h"
#include "photon/map/photon_map.h"
#include "render/photon_map/volume_estimate.h"

namespace vpm {

class RunDecisionMap {
public:
    // An eighth of photons.count: at photons.count it cost the dense box of optical side 100 as much
    // as the pass's own photon pass (docs/studies/heldout_scenes.md, section 31).
    static constexpr int64_t kShare = 8;

    RunDecisionMap() = default;
    RunDecisionMap(const RunDecisionMap&) = delete;   // map_ may point into owned_
    RunDecisionMap& operator=(const RunDecisionMap&) = delete;

    // Keeps `map`, traced at `emitted` photons; the ratio follows the pass maps' photons.
    void own(PhotonMap map, double emitted) {
        owned_ = std::move(map);
        map_ = &owned_;
        cells_ = PhotonCellCounts(owned_);
        emitted_ = emitted;
        set_map_emitted(map_emitted_);
    }
    // Decides on `map` (null: on each estimate's own list) with the ratio given.
    void use(const PhotonMap* map, double ratio) {
        map_ = map;
        cells_ = map ? PhotonCellCounts(*map) : PhotonCellCounts();
        emitted_ = 0.0;
        ratio_ = ratio;
    }
    // The pass's volume map was traced at `emitted` photons.
    void set_map_emitted(double emitted) {
        map_emitted_ = emitted;
        if (emitted_ > 0.0) ratio_ = emitted / emitted_;
    }
    // What the pass's estimates decide on; for_map: for a volume map of `emitted` photons (a pilot's).
    DecisionMap view() const { return {map_, &cells_, ratio_}; }
    DecisionMap for_map(double emitted) const { return {map_, &cells_, emitted_ > 0.0 ? emitted / emitted_ : ratio_}; }
    const PhotonMap* map() const { return map_; }

private:
    PhotonMap owned_;
    const PhotonMap* map_ = nullptr;
    PhotonCellCounts cells_;     // answers most decisions in thin media without a query
    double ratio_ = 1.0;         // emitted photons of the pass's volume map per one of the decision map's
    double emitted_ = 0.0;       // the owned map's emitted photons (0: given)
    double map_emitted_ = 0.0;   // the pass's volume map's emitted photons (owned maps)
};

}  // namespace vpm
