#pragma once
// Tracking work done by this thread in grid media, in three counts: steps (majorant-walk DDA cells
// plus tentative collisions, real and null, of delta and ratio tracking), point density lookups, and
// voxel cells integrated in closed form (the stiff tracking's exact segments and the march's optical-
// depth profile). Thread-local running counts, read before and after one camera sample on the same
// thread, give that sample's: counts that do not depend on the thread or the machine. The auto
// pilot's work units use them (render/plan/work_units.h): a grid ray's cost follows its null
// collisions (steps), its lookups and its closed-form cells, each of which dominates some gather
// (docs/studies/auto_plan.md sections 11.7 and 28).
#include <cstdint>

#include "scene/media/majorant_tracking.h"

namespace vpm {

struct TrackingCounts {
    uint64_t steps = 0;     // DDA cells and tentative collisions
    uint64_t lookups = 0;   // point density lookups
    uint64_t cells = 0;     // voxel cells integrated in closed form
};

// This thread's counts so far (each wraps after 2^64).
TrackingCounts& thread_tracking_counts();

inline void count_tracking(const TrackingStats& st) {
    TrackingCounts& c = thread_tracking_counts();
    c.steps += uint64_t(st.blocks + st.tentative);
    c.lookups += uint64_t(st.lookups);
    c.cells += uint64_t(st.cells);
}

}  // namespace vpm
