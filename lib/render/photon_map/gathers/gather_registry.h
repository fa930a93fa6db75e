#pragma once
// The photon map's camera-side gathers by name: photons.gather's values. One table (gather_registry.cpp)
// that the settings reader, the run record's gather_used, the automatic plan's candidates, `vpm render
// --help` and the documentation check (tests/tools/registry_docs_test.cpp) all read.
//
// A gather decides what a camera segment through the media takes from the pass's maps: one estimate
// where the free flight collides ("collision"), points along the segment ("march"), or one query over
// a BVH of photon discs ("point_beam") or photon beams ("photon_beams"). "auto" and "pilot" choose one
// of them per run or per pass; "threshold" per segment.
#include <memory>
#include <string>
#include <vector>

namespace vpm {

class SegmentGather;
struct SegmentGatherInputs;

enum class GatherMode { collision, march, automatic, pilot, threshold, point_beam, photon_beams };

struct GatherEntry {
    const char* name;          // photons.gather's value, and the run record's gather_used
    GatherMode mode;
    const char* summary;       // one line: what the camera side does
    bool chooses;              // picks another gather per run or pass ("auto", "pilot"): never in force itself
    bool plan_measures;        // the map-noise pilot measures it: a candidate of the automatic plan, whose
                               // time-limit sizing then applies to it
    bool stores_beams;         // the photon pass records the photons' free flights as beams, not volume photons
    bool uses_decision_map;    // its estimates follow photons.max_radius_mfp's switch (the decision map)
    // The per-pass structure of a segment gather (segment_gather.h); null for the point gathers.
    std::unique_ptr<SegmentGather> (*build)(SegmentGatherInputs& inputs);
};

// The gathers in the order lists show them.
const std::vector<GatherEntry>& gather_entries();
std::vector<std::string> gather_names();
const GatherEntry& gather_entry(GatherMode mode);
// The entry called `name` (old names included: "beam" for "point_beam"), or nullptr.
const GatherEntry* find_gather(const std::string& name);
// The old names still accepted, with the note the reader prints for them.
struct GatherAlias {
    const char* name;
    GatherMode mode;
    const char* note;
};
const std::vector<GatherAlias>& gather_aliases();

}  // namespace vpm
