#include "render/photon_map/gathers/gather_registry.h"

#include <stdexcept>

#include "core/registry.h"
#include "render/photon_map/gathers/segment_gather.h"

namespace vpm {

// The segment gathers' build functions, one beside each file pair.
std::unique_ptr<SegmentGather> build_point_beam_gather(SegmentGatherInputs& inputs);     // point_beam_gather.cpp
std::unique_ptr<SegmentGather> build_photon_beams_gather(SegmentGatherInputs& inputs);   // photon_beams_gather.cpp

const std::vector<GatherEntry>& gather_entries() {
    static const std::vector<GatherEntry> entries = {
        {"auto", GatherMode::automatic,
         "the run's first pass measures collision and march and keeps the least error for its work (docs/passes.md)",
         true, false, false, true, nullptr},
        {"collision", GatherMode::collision, "one estimate where the camera ray's free flight collides", false, true, false, true,
         nullptr},
        {"march", GatherMode::march, "gather_queries stratified points along every camera segment in the media", false,
         true, false, true, nullptr},
        {"threshold", GatherMode::threshold,
         "per segment: march where its majorant optical depth is at most march_max_optical_depth, else collision",
         false, false, false, true, nullptr},
        {"pilot", GatherMode::pilot, "each pass keeps the least variance x cost of collision, march and threshold",
         true, false, false, true, nullptr},
        {"point_beam", GatherMode::point_beam,
         "one query per segment over a BVH of the photons' discs (docs/beam_estimate.md)", false, false, false,
         false, build_point_beam_gather},
        {"photon_beams", GatherMode::photon_beams,
         "the photon paths' free flights as beams, the 1D beam x beam estimate (docs/photon_beams.md)", false, false,
         true, false, build_photon_beams_gather},
    };
    return entries;
}

const std::vector<GatherAlias>& gather_aliases() {
    static const std::vector<GatherAlias> aliases = {
        {"beam", GatherMode::point_beam,
         "\"beam\" is the old name of \"point_beam\" (the beam radiance estimate over photon points); "
         "\"photon_beams\" is the photon-beams gather (docs/photon_beams.md)"},
    };
    return aliases;
}

std::vector<std::string> gather_names() { return registry_names(gather_entries()); }

const GatherEntry& gather_entry(GatherMode mode) {
    for (const GatherEntry& e : gather_entries())
        if (e.mode == mode) return e;
    throw std::logic_error("gather_entry: a GatherMode without a registry entry");
}

const GatherEntry* find_gather(const std::string& name) {
    if (const GatherEntry* e = registry_find(gather_entries(), name)) return e;
    for (const GatherAlias& a : gather_aliases())
        if (name == a.name) return &gather_entry(a.mode);
    return nullptr;
}

}  // namespace vpm
