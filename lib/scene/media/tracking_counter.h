#pragma once
// Tracking steps taken by this thread in grid media: majorant-walk steps (DDA cells) plus tentative
// collisions, real and null, of delta and ratio tracking. A thread-local running count, read before
// and after one camera sample on the same thread, gives that sample's steps: a count that does not
// depend on the thread or the machine. The auto pilot's work units use it (render/work_units.h):
// without it a grid ray's cost was one figure whatever its null collisions (the thin plume's
// collision gather cost 4x less than counted, BENCHMARKS.md section 11.7).
#include <cstdint>

#include "scene/media/majorant_tracking.h"

namespace vpm {

// This thread's steps so far (wraps after 2^64).
uint64_t& thread_tracking_steps();

inline void count_tracking_steps(const TrackingStats& st) {
    thread_tracking_steps() += uint64_t(st.blocks + st.tentative);
}

}  // namespace vpm
