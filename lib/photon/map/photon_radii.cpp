#include "photon/map/photon_radii.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

namespace vpm {

std::vector<double> photon_radii(const PhotonMap& map, size_t k) {
    std::vector<double> radii(map.size(), kInfinity);
    if (k == 0 || map.size() <= k) return radii;
    tbb::enumerable_thread_specific<NeighbourList> lists;
    tbb::parallel_for(tbb::blocked_range<size_t>(0, map.size(), 1024), [&](const tbb::blocked_range<size_t>& range) {
        NeighbourList& list = lists.local();
        for (size_t i = range.begin(); i != range.end(); ++i) {
            // k + 1 nearest including the photon itself (distance 0, or a coincident twin: either
            // way one of the k + 1 is this photon's own slot, so the last is its k-th other).
            map.knn(map.position(i), k + 1, kInfinity, list);
            radii[i] = list.max_distance();
        }
    });
    return radii;
}

}  // namespace vpm
