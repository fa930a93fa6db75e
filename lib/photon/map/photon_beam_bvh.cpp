#include "photon/map/photon_beam_bvh.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.h"
#include "photon/map/segment_box_distance.h"

namespace vpm {

namespace {

// (u, index) order: the k nearest are the same set on any traversal.
bool closer(const BeamCrossing& a, const BeamCrossing& b) { return a.u < b.u || (a.u == b.u && a.index < b.index); }

// A node of the best-first traversal's queue: its box's max-norm distance to the segment.
struct Open {
    double distance;
    uint32_t node;
};
// Min-heap on (distance, node): the node order, and so the tested count, are deterministic.
bool farther(const Open& a, const Open& b) { return a.distance > b.distance || (a.distance == b.distance && a.node > b.node); }

// The nodes build() makes for n items (median splits down to leaves of at most 4).
size_t node_count_for(uint32_t n) { return n <= 4 ? 1 : 1 + node_count_for(n / 2) + node_count_for(n - n / 2); }

}  // namespace

double PhotonBeamBvh::automatic_piece_length(const std::vector<PhotonBeam>& beams) {
    Bounds3 box;
    double total = 0.0;
    size_t n = 0;
    for (const PhotonBeam& b : beams) {
        if (!(b.length > 0.0) || !std::isfinite(b.length) || !b.origin.allFinite() || !b.dir.allFinite()) continue;
        box.extend(b.origin);
        box.extend(b.origin + b.length * b.dir);
        total += b.length;
        ++n;
    }
    if (n == 0) return 0.0;
    const double mean = total / double(n);
    const Vec3 e = box.hi - box.lo;
    const double volume = e.x() * e.y() * e.z();
    const double spacing = volume > 0.0 ? 4.0 / std::sqrt(total / volume) : 0.0;
    return std::clamp(spacing, mean / kPiecesPerMeanLength, mean);
}

uint32_t PhotonBeamBvh::pieces(const PhotonBeam& b, double max_piece) {
    if (!(b.length > 0.0) || !std::isfinite(b.length) || !b.origin.allFinite() || !b.dir.allFinite()) return 0;
    const double m = max_piece > 0.0 && std::isfinite(max_piece) ? std::min(std::ceil(b.length / max_piece), 1e6) : 1.0;
    return uint32_t(std::max(m, 1.0));
}

PhotonBeamBvh::PhotonBeamBvh(const std::vector<PhotonBeam>& beams, const std::vector<double>& radii, double max_piece,
                             bool per_piece) {
    // Pieces of beam i (0: left out). Counted first so that the items are allocated once, at their
    // size (max_bytes_per_beam, the photon pass's memory projection, counts no growth).
    auto pieces_of = [&](size_t i) -> uint32_t {
        if (per_piece || radii.empty()) return pieces(beams[i], max_piece);
        const double w = radii[i];
        if (!std::isfinite(w) || !(w > 0.0)) return 0;   // a sample-point width of 0 crosses nothing
        return pieces(beams[i], max_piece);
    };
    auto usable = [](double w) { return std::isfinite(w) && w > 0.0; };
    size_t total = 0;
    for (size_t i = 0; i < beams.size(); ++i) total += pieces_of(i);
    if (per_piece && radii.size() != total)
        throw Error("photon beam BVH: " + std::to_string(radii.size()) + " piece widths for " + std::to_string(total) + " pieces");
    items_.reserve(total);
    size_t piece = 0;   // per_piece: the running index into radii
    for (size_t i = 0; i < beams.size(); ++i) {
        const uint32_t m = pieces_of(i);
        if (m == 0) continue;
        const PhotonBeam& b = beams[i];
        bool kept = false;
        for (uint32_t p = 0; p < m; ++p, ++piece) {
            const double w = per_piece ? radii[piece] : radii.empty() ? 0.0 : radii[i];
            if (per_piece && !usable(w)) continue;
            // The same expression for a piece's end and the next one's start: the pieces tile [0, length].
            items_.push_back({b.origin, b.dir, b.length, w, piece_start(b, p, m), piece_end(b, p, m), uint32_t(i)});
            kept = true;
        }
        if (kept) ++beam_count_;
    }
    if (items_.empty()) return;
    nodes_.reserve(node_count_for(uint32_t(items_.size())));
    build(0, uint32_t(items_.size()));
}

uint32_t PhotonBeamBvh::build(uint32_t begin, uint32_t end) {
    const uint32_t index = uint32_t(nodes_.size());
    nodes_.push_back({});
    if (end - begin <= 4) {
        Bounds3 bounds;
        for (uint32_t i = begin; i < end; ++i) {
            const Item& b = items_[i];
            const Vec3 a = b.origin + b.v0 * b.dir, z = b.origin + b.v1 * b.dir;
            // Padded so that rounding in the box test never drops a beam the exact leaf test accepts.
            const double scale = std::max({a.cwiseAbs().maxCoeff(), z.cwiseAbs().maxCoeff(), b.origin.cwiseAbs().maxCoeff()});
            const Vec3 r = Vec3::Constant(b.width * (1.0 + 1e-9) + 1e-9 * std::max(scale, b.length) + 1e-300);
            bounds.extend(Bounds3{a.cwiseMin(z) - r, a.cwiseMax(z) + r});
        }
        nodes_[index] = {bounds, begin, end - begin};
        return index;
    }
    auto mid_point = [](const Item& b) { return Vec3(b.origin + 0.5 * (b.v0 + b.v1) * b.dir); };
    Bounds3 mids;
    for (uint32_t i = begin; i < end; ++i) mids.extend(mid_point(items_[i]));
    int axis = 0;
    (mids.hi - mids.lo).maxCoeff(&axis);
    const uint32_t mid = begin + (end - begin) / 2;
    auto key = [axis](const Item& b) { return b.origin[axis] + 0.5 * (b.v0 + b.v1) * b.dir[axis]; };
    std::nth_element(items_.begin() + begin, items_.begin() + mid, items_.begin() + end, [&](const Item& a, const Item& b) {
        const double ka = key(a), kb = key(b);
        return ka < kb || (ka == kb && (a.index < b.index || (a.index == b.index && a.v0 < b.v0)));
    });
    const uint32_t first = build(begin, mid);   // index + 1
    const uint32_t second = build(mid, end);
    // The children's boxes are made first: a node's box is their union (the same as over its items).
    Bounds3 bounds = nodes_[first].bounds;
    bounds.extend(nodes_[second].bounds);
    nodes_[index] = {bounds, second, 0};
    return index;
}

void PhotonBeamBvh::nearest(const Vec3& origin, const Vec3& dir, double tmax, size_t k, double max_distance,
                            std::vector<BeamCrossing>& out, uint32_t skip, uint64_t* tested) const {
    out.clear();
    if (nodes_.empty() || k == 0 || !(tmax >= 0.0)) return;
    // out is a max-heap on (u, index) of at most k crossings; bound: the k-th's u once full.
    auto bound = [&] { return out.size() < k ? max_distance : out.front().u; };
    // A node is opened only if its distance is within the bound (slack for the rounding of u and
    // of the distance: a beam at u equal to the bound may still enter on a smaller index).
    auto reachable = [&](double distance) {
        const double b = bound();
        return !std::isfinite(b) || distance <= b * (1.0 + 1e-9);
    };
    thread_local std::vector<Open> queue;
    queue.clear();
    queue.push_back({segment_box_distance_max_norm(nodes_[0].bounds, origin, dir, tmax), 0});
    while (!queue.empty()) {
        std::pop_heap(queue.begin(), queue.end(), farther);
        const Open top = queue.back();
        queue.pop_back();
        if (!reachable(top.distance)) break;   // every node left is at least as far
        const Node& node = nodes_[top.node];
        if (node.count == 0) {
            for (const uint32_t child : {top.node + 1, node.first}) {
                // The cheap tests first: the slab, then the line bound; the max-norm one last.
                const Bounds3& box = nodes_[child].bounds;
                if (!box_meets_segment_slab(box, origin, dir, tmax)) continue;   // no crossing inside
                const double line = box_line_distance_sphere(box, origin, dir);
                if (!reachable(line)) continue;
                const double d = std::max(line, segment_box_distance_max_norm(box, origin, dir, tmax));
                if (!reachable(d)) continue;
                queue.push_back({d, child});
                std::push_heap(queue.begin(), queue.end(), farther);
            }
            continue;
        }
        if (tested) *tested += node.count;
        for (uint32_t i = node.first; i < node.first + node.count; ++i) {
            const Item& it = items_[i];
            if (it.index == skip) continue;
            BeamCrossing c;
            if (!crosses(origin, dir, tmax, it, c)) continue;
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
