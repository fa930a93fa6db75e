#include "scene/media/tracking_counter.h"

namespace vpm {

uint64_t& thread_tracking_steps() {
    thread_local uint64_t steps = 0;
    return steps;
}

}  // namespace vpm
