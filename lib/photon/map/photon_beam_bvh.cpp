#include "photon/map/photon_beam_bvh.h"

#include <algorithm>
#include <cmath>

namespace vpm {

namespace {

// (u, index) order: the k nearest are the same set on any traversal.
bool closer(const BeamCrossing& a, const BeamCrossing& b) { return a.u < b.u || (a.u == b.u && a.index < b.index); }

// The box grown by r on every side, slab-tested against the segment: a superset of the points
// within distance r of the box.
bool grown_box_hit(const Bounds3& b, double r, const Ray& ray, double tmax) {
    if (!std::isfinite(r)) return true;
    const Vec3 pad = Vec3::Constant(r * (1.0 + 1e-9));
    double t0, t1;
    return Bounds3{b.lo - pad, b.hi + pad}.intersect(ray, tmax, t0, t1);
}

// Squared distance from p to the segment: the order children are visited in (any order is exact).
double segment_distance2(const Vec3& p, const Ray& ray, double tmax) {
    double t = (p - ray.origin).dot(ray.dir);
    t = std::clamp(t, 0.0, std::isfinite(tmax) ? tmax : std::max(t, 0.0));
    return (ray.at(t) - p).squaredNorm();
}

}  // namespace

PhotonBeamBvh::PhotonBeamBvh(const std::vector<PhotonBeam>& beams, const std::vector<double>& radii) {
    for (size_t i = 0; i < beams.size(); ++i) {
        const PhotonBeam& b = beams[i];
        const double w = radii.empty() ? 0.0 : radii[i];
        if (!(b.length > 0.0) || !std::isfinite(b.length) || !std::isfinite(w) || !(w >= 0.0) || !b.origin.allFinite() ||
            !b.dir.allFinite())
            continue;
        if (!radii.empty() && !(w > 0.0)) continue;   // a sample-point width of 0 crosses nothing
        items_.push_back({b.origin, b.dir, b.length, w, uint32_t(i)});
    }
    if (items_.empty()) return;
    nodes_.reserve(items_.size() / 2 + 1);
    build(0, uint32_t(items_.size()));
}

uint32_t PhotonBeamBvh::build(uint32_t begin, uint32_t end) {
    const uint32_t index = uint32_t(nodes_.size());
    nodes_.push_back({});
    Bounds3 bounds, mids;
    for (uint32_t i = begin; i < end; ++i) {
        const Item& b = items_[i];
        const Vec3 a = b.origin, z = b.origin + b.length * b.dir;
        // Padded so that rounding in the box test never drops a beam the exact leaf test accepts.
        const double scale = std::max(a.cwiseAbs().maxCoeff(), z.cwiseAbs().maxCoeff());
        const Vec3 r = Vec3::Constant(b.width * (1.0 + 1e-9) + 1e-9 * scale + 1e-300);
        bounds.extend(Bounds3{a.cwiseMin(z) - r, a.cwiseMax(z) + r});
        mids.extend(0.5 * (a + z));
    }
    nodes_[index].bounds = bounds;
    if (end - begin <= 4) {
        nodes_[index].first = begin;
        nodes_[index].count = end - begin;
        return index;
    }
    int axis = 0;
    (mids.hi - mids.lo).maxCoeff(&axis);
    const uint32_t mid = begin + (end - begin) / 2;
    auto key = [axis](const Item& b) { return b.origin[axis] + 0.5 * b.length * b.dir[axis]; };
    std::nth_element(items_.begin() + begin, items_.begin() + mid, items_.begin() + end, [&](const Item& a, const Item& b) {
        const double ka = key(a), kb = key(b);
        return ka < kb || (ka == kb && a.index < b.index);
    });
    build(begin, mid);   // the first child is index + 1
    const uint32_t second = build(mid, end);
    nodes_[index].first = second;
    nodes_[index].count = 0;
    return index;
}

void PhotonBeamBvh::nearest(const Vec3& origin, const Vec3& dir, double tmax, size_t k, double max_distance,
                            std::vector<BeamCrossing>& out, uint32_t skip, uint64_t* tested) const {
    out.clear();
    if (nodes_.empty() || k == 0 || !(tmax >= 0.0)) return;
    const Ray ray{origin, dir};
    // out is a max-heap on (u, index) of at most k crossings; bound: the k-th's u once full.
    auto bound = [&] { return out.size() < k ? max_distance : out.front().u; };
    uint32_t stack[64];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
        const Node& node = nodes_[stack[--top]];
        if (!grown_box_hit(node.bounds, bound(), ray, tmax)) continue;
        if (node.count == 0) {
            const uint32_t a = uint32_t(&node - nodes_.data()) + 1, b = node.first;
            const bool a_first = segment_distance2(0.5 * (nodes_[a].bounds.lo + nodes_[a].bounds.hi), ray, tmax) <=
                                 segment_distance2(0.5 * (nodes_[b].bounds.lo + nodes_[b].bounds.hi), ray, tmax);
            stack[top++] = a_first ? b : a;   // the nearer child is popped first
            stack[top++] = a_first ? a : b;
            continue;
        }
        if (tested) *tested += node.count;
        for (uint32_t i = node.first; i < node.first + node.count; ++i) {
            const Item& it = items_[i];
            if (it.index == skip) continue;
            BeamCrossing c;
            if (!photon_beam_crossing(origin, dir, tmax, it.origin, it.dir, it.length, c)) continue;
            c.index = it.index;
            if (!(c.u < max_distance)) continue;
            if (out.size() < k) {
                out.push_back(c);
                std::push_heap(out.begin(), out.end(), closer);
            } else if (closer(c, out.front())) {
                std::pop_heap(out.begin(), out.end(), closer);
                out.back() = c;
                std::push_heap(out.begin(), out.end(), closer);
            }
        }
    }
    std::sort_heap(out.begin(), out.end(), closer);
}

}  // namespace vpm
