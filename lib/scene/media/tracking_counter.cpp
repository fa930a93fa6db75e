#include "scene/media/tracking_counter.h"

namespace vpm {

TrackingCounts& thread_tracking_counts() {
    thread_local TrackingCounts counts;
    return counts;
}

}  // namespace vpm
