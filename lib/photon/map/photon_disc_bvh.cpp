#include "photon/map/photon_disc_bvh.h"

#include <algorithm>
#include <cmath>

namespace vpm {

PhotonDiscBvh::PhotonDiscBvh(const std::vector<Vec3>& centres, const std::vector<double>& radii) {
    for (size_t i = 0; i < centres.size(); ++i)
        if (std::isfinite(radii[i]) && radii[i] > 0.0 && centres[i].allFinite())
            balls_.push_back({centres[i], radii[i], uint32_t(i)});
    if (balls_.empty()) return;
    nodes_.reserve(balls_.size() / 2 + 1);
    build(0, uint32_t(balls_.size()));
}

uint32_t PhotonDiscBvh::build(uint32_t begin, uint32_t end) {
    const uint32_t index = uint32_t(nodes_.size());
    nodes_.push_back({});
    Bounds3 bounds, centres;
    for (uint32_t i = begin; i < end; ++i) {
        // Padded so that rounding in the box test never drops a ball the exact leaf test accepts.
        const Vec3 r = Vec3::Constant(balls_[i].radius * (1.0 + 1e-9) + 1e-12 * balls_[i].centre.cwiseAbs().maxCoeff());
        bounds.extend(Bounds3{balls_[i].centre - r, balls_[i].centre + r});
        centres.extend(balls_[i].centre);
    }
    nodes_[index].bounds = bounds;
    if (end - begin <= 4) {
        nodes_[index].first = begin;
        nodes_[index].count = end - begin;
        return index;
    }
    int axis = 0;
    (centres.hi - centres.lo).maxCoeff(&axis);
    const uint32_t mid = begin + (end - begin) / 2;
    // Ties by index: the same photons give the same tree on any standard library.
    std::nth_element(balls_.begin() + begin, balls_.begin() + mid, balls_.begin() + end, [axis](const Ball& a, const Ball& b) {
        return a.centre[axis] < b.centre[axis] || (a.centre[axis] == b.centre[axis] && a.index < b.index);
    });
    build(begin, mid);   // the first child is index + 1
    const uint32_t second = build(mid, end);
    nodes_[index].first = second;
    nodes_[index].count = 0;
    return index;
}

}  // namespace vpm
