#include "photon/photon_map.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>

#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include "core/error.h"

namespace vpm {

namespace {

// k nearest with an upper bound on the squared distance: the tree prunes with
// min(current k-th distance, radius^2), so a small max_radius makes queries cheaper.
// (Same interface as a nanoflann result set.)
class KnnRadiusResultSet {
public:
    using DistanceType = float;
    using IndexType = uint32_t;
    KnnRadiusResultSet(uint32_t* idx, float* d2, size_t capacity, float radius2)
        : idx_(idx), d2_(d2), cap_(capacity), radius2_(radius2) {}
    size_t size() const { return count_; }
    bool full() const { return count_ == cap_; }
    float worstDist() const { return count_ == cap_ ? d2_[cap_ - 1] : radius2_; }
    bool addPoint(float dist, uint32_t index) {
        if (dist >= worstDist()) return true;
        size_t i = count_ < cap_ ? count_ : cap_ - 1;
        for (; i > 0 && d2_[i - 1] > dist; --i) {
            d2_[i] = d2_[i - 1];
            idx_[i] = idx_[i - 1];
        }
        d2_[i] = dist;
        idx_[i] = index;
        if (count_ < cap_) ++count_;
        return true;
    }

private:
    uint32_t* idx_;
    float* d2_;
    size_t cap_;
    size_t count_ = 0;
    float radius2_;
};

// Spreads the low 21 bits of v to every third bit.
uint64_t spread_bits(uint64_t v) {
    v &= 0x1fffff;
    v = (v | v << 32) & 0x1f00000000ffffULL;
    v = (v | v << 16) & 0x1f0000ff0000ffULL;
    v = (v | v << 8) & 0x100f00f00f00f00fULL;
    v = (v | v << 4) & 0x10c30c30c30c30c3ULL;
    v = (v | v << 2) & 0x1249249249249249ULL;
    return v;
}

}  // namespace

// The kd-tree over the Morton-sorted records. Splits follow the Morton bits (an implicit
// octree refined one axis at a time), so a node is a contiguous range of the stored order and no
// permutation array is needed; building is a binary search per node plus one pass over the
// positions for the bounding boxes. Each inner node stores the largest coordinate of its left
// child and the smallest of its right child along its axis (nanoflann's divlow/divhigh), and the
// search is nanoflann's (incremental distance to the cell, nearer child first).
struct PhotonMap::Index {
    struct Node {
        float lo, hi;       // inner: max of the left child, min of the right child along `info`
        uint32_t a;         // inner: index of the right child (the left one is next); leaf: begin
        uint32_t info;      // inner: axis 0..2; leaf: (count << 2) | 3
    };
    static_assert(sizeof(Node) == 16, "kd-tree node must stay 16 bytes");
    std::vector<Node> nodes;
    float root_lo[3] = {0, 0, 0}, root_hi[3] = {0, 0, 0};
    const Photon* data = nullptr;

    struct Box {
        float lo[3], hi[3];
    };

    // Builds the subtree over [begin, end) whose keys agree above bit `bit`; returns its box.
    Box build(const uint64_t* keys, uint32_t begin, uint32_t end, int bit, size_t leaf) {
        // Skip bits on which the whole range agrees (no node for them).
        uint32_t mid = begin;
        while (end - begin > leaf && bit >= 0) {
            const uint64_t mask = uint64_t(1) << bit;
            mid = uint32_t(std::partition_point(keys + begin, keys + end, [&](uint64_t k) { return !(k & mask); }) -
                           keys);
            if (mid != begin && mid != end) break;
            --bit;
        }
        const uint32_t self = uint32_t(nodes.size());
        nodes.emplace_back();
        if (end - begin <= leaf || bit < 0) {   // leaf (bit < 0: identical keys, an oversized leaf)
            if (uint64_t(end - begin) >= (uint64_t(1) << 30))
                throw Error("photon map: over 2^30 photons at one quantised position");
            nodes[self].a = begin;
            nodes[self].info = ((end - begin) << 2) | 3u;
            Box b;
            for (int d = 0; d < 3; ++d) {
                b.lo[d] = std::numeric_limits<float>::infinity();
                b.hi[d] = -std::numeric_limits<float>::infinity();
            }
            for (uint32_t i = begin; i < end; ++i)
                for (int d = 0; d < 3; ++d) {
                    b.lo[d] = std::min(b.lo[d], data[i].p[d]);
                    b.hi[d] = std::max(b.hi[d], data[i].p[d]);
                }
            return b;
        }
        const int axis = bit % 3;
        const Box left = build(keys, begin, mid, bit - 1, leaf);
        nodes[self].a = uint32_t(nodes.size());
        const Box right = build(keys, mid, end, bit - 1, leaf);
        nodes[self].info = uint32_t(axis);
        nodes[self].lo = left.hi[axis];
        nodes[self].hi = right.lo[axis];
        Box b;
        for (int d = 0; d < 3; ++d) {
            b.lo[d] = std::min(left.lo[d], right.lo[d]);
            b.hi[d] = std::max(left.hi[d], right.hi[d]);
        }
        return b;
    }

    void search(uint32_t idx, const float q[3], float mindist, float dists[3], KnnRadiusResultSet& rs) const {
        const Node& n = nodes[idx];
        if ((n.info & 3u) == 3u) {
            const uint32_t end = n.a + (n.info >> 2);
            float worst = rs.worstDist();
            for (uint32_t i = n.a; i < end; ++i) {
                const float* p = data[i].p;
                const float dx = q[0] - p[0], dy = q[1] - p[1], dz = q[2] - p[2];
                const float d = dx * dx + dy * dy + dz * dz;
                if (d < worst) {
                    rs.addPoint(d, i);
                    worst = rs.worstDist();
                }
            }
            return;
        }
        const int axis = int(n.info);
        const float v = q[axis];
        const float diff1 = v - n.lo, diff2 = v - n.hi;
        uint32_t best, other;
        float cut;
        if (diff1 + diff2 < 0) {
            best = idx + 1;
            other = n.a;
            cut = diff2 * diff2;
        } else {
            best = n.a;
            other = idx + 1;
            cut = diff1 * diff1;
        }
        search(best, q, mindist, dists, rs);
        const float saved = dists[axis];
        mindist = mindist + cut - saved;
        dists[axis] = cut;
        if (mindist <= rs.worstDist()) search(other, q, mindist, dists, rs);
        dists[axis] = saved;
    }

    void knn(const float q[3], KnnRadiusResultSet& rs) const {
        float dists[3];
        float mindist = 0;
        for (int d = 0; d < 3; ++d) {
            dists[d] = 0;
            if (q[d] < root_lo[d]) dists[d] = (q[d] - root_lo[d]) * (q[d] - root_lo[d]);
            else if (q[d] > root_hi[d]) dists[d] = (q[d] - root_hi[d]) * (q[d] - root_hi[d]);
            mindist += dists[d];
        }
        search(0, q, mindist, dists, rs);
    }
};

PhotonMap::PhotonMap() = default;
PhotonMap::~PhotonMap() = default;
PhotonMap::PhotonMap(PhotonMap&&) noexcept = default;
PhotonMap& PhotonMap::operator=(PhotonMap&&) noexcept = default;

PhotonMap::PhotonMap(const std::vector<PhotonInput>& in, size_t leaf_size) {
    if (in.size() >= std::numeric_limits<uint32_t>::max())
        throw Error("photon map: too many photons (" + std::to_string(in.size()) + ", max 2^32-2)");
    double max_power = 0.0;
    for (size_t i = 0; i < in.size(); ++i) {
        const PhotonInput& p = in[i];
        if (!p.position.allFinite())
            throw Error("photon map: photon " + std::to_string(i) + " has a non-finite position");
        if (!all_finite(p.power))
            throw Error("photon map: photon " + std::to_string(i) + " has non-finite power");
        bounds_.extend(p.position);
        max_power = std::max(max_power, p.power.maxCoeff());
    }
    if (in.empty()) return;
    centre_ = 0.5 * (bounds_.lo + bounds_.hi);
    power_scale_ = max_power > 0.0 ? max_power : 1.0;
    const double inv_scale = 1.0 / power_scale_;

    // Morton order over the bounds for cache coherence of leaves and of neighbouring queries;
    // the kd-tree splits along the same bits. Key and encoding passes run in parallel; ties in
    // the key are ordered by input index, so the stored order is deterministic.
    const Vec3 extent = (bounds_.hi - bounds_.lo).cwiseMax(Vec3::Constant(1e-300));
    // Pass 1 reads the input sequentially: Morton key and the encoded record in input order.
    // Pass 2 gathers the 24-byte records (not the 72-byte inputs) in key order with prefetching:
    // for photons in path order the permutation is random, and the gather is memory bound.
    std::vector<std::pair<uint64_t, uint32_t>> keys(in.size());
    std::vector<Photon> unsorted(in.size());
    tbb::parallel_for(tbb::blocked_range<size_t>(0, in.size(), 16384), [&](const tbb::blocked_range<size_t>& r) {
        for (size_t i = r.begin(); i < r.end(); ++i) {
            const PhotonInput& p = in[i];
            const Vec3 t = ((p.position - bounds_.lo).array() / extent.array()).matrix();
            uint64_t code = 0;
            for (int a = 0; a < 3; ++a) {
                const double q = std::min(std::max(t[a], 0.0), 1.0) * 2097151.0;
                code |= spread_bits(static_cast<uint64_t>(q)) << a;
            }
            keys[i] = {code, static_cast<uint32_t>(i)};
            Photon& rec = unsorted[i];
            const Vec3 rel = p.position - centre_;
            for (int a = 0; a < 3; ++a) rec.p[a] = static_cast<float>(rel[a]);
            encode_direction(p.direction, rec.dir);
            encode_power(p.power, inv_scale, rec.power);
            rec.reserved = 0;
        }
    });
    tbb::parallel_sort(keys.begin(), keys.end());

    photons_.resize(in.size());
    std::vector<uint64_t> codes(in.size());
    tbb::parallel_for(tbb::blocked_range<size_t>(0, in.size(), 16384), [&](const tbb::blocked_range<size_t>& r) {
        constexpr size_t kAhead = 16;
        for (size_t j = r.begin(); j < r.end(); ++j) {
            if (j + kAhead < r.end()) __builtin_prefetch(&unsorted[keys[j + kAhead].second]);
            photons_[j] = unsorted[keys[j].second];
            codes[j] = keys[j].first;
        }
    });
    std::vector<Photon>().swap(unsorted);
    std::vector<std::pair<uint64_t, uint32_t>>().swap(keys);
    index_ = std::make_unique<Index>();
    index_->data = photons_.data();
    index_->nodes.reserve(2 * (in.size() / std::max<size_t>(1, leaf_size / 2) + 1));
    const Index::Box root = index_->build(codes.data(), 0, uint32_t(in.size()), 62, std::max<size_t>(1, leaf_size));
    index_->nodes.shrink_to_fit();
    for (int d = 0; d < 3; ++d) {
        index_->root_lo[d] = root.lo[d];
        index_->root_hi[d] = root.hi[d];
    }
}

size_t PhotonMap::knn(const Vec3& query, size_t k, double max_radius, NeighbourList& out) const {
    out.items.clear();
    if (k == 0 || photons_.empty() || !(max_radius >= 0.0)) return 0;
    k = std::min(k, photons_.size());
    if (out.scratch_index.size() < k) {
        out.scratch_index.resize(k);
        out.scratch_d2.resize(k);
    }
    const Vec3 rel = query - centre_;
    const float q[3] = {static_cast<float>(rel[0]), static_cast<float>(rel[1]), static_cast<float>(rel[2])};
    const bool limited = std::isfinite(max_radius);
    const double max_r2 = max_radius * max_radius;
    // Float search bound with a margin covering the float rounding of stored positions and of
    // the query (each <= 2^-24 of the coordinate magnitude per axis); the exact double test is
    // applied below.
    const double coord = rel.cwiseAbs().maxCoeff() + 0.5 * (bounds_.hi - bounds_.lo).cwiseAbs().maxCoeff();
    const double slack = 8.0 * 0x1p-24 * coord;
    const float bound = limited ? static_cast<float>((max_radius + slack) * (max_radius + slack) * (1.0 + 1e-6))
                                : std::numeric_limits<float>::max();
    KnnRadiusResultSet rs(out.scratch_index.data(), out.scratch_d2.data(), k, bound);
    index_->knn(q, rs);
    const size_t found = rs.size();
    if (out.items.capacity() < k) out.items.reserve(k);
    for (size_t i = 0; i < found; ++i) {
        const uint32_t idx = out.scratch_index[i];
        const Photon& p = photons_[idx];
        const Vec3 d = rel - Vec3(p.p[0], p.p[1], p.p[2]);
        const double d2 = d.squaredNorm();
        if (limited && d2 > max_r2) continue;
        Neighbour n;
        n.index = idx;
        n.d2 = d2;
        n.power = decode_power(p.power, power_scale_);
        n.direction = decode_direction(p.dir);
        out.items.push_back(n);
    }
    std::sort(out.items.begin(), out.items.end(), [](const Neighbour& a, const Neighbour& b) {
        return a.d2 < b.d2 || (a.d2 == b.d2 && a.index < b.index);
    });
    return out.items.size();
}

Rgb PhotonMap::total_power() const {
    Rgb sum = Rgb::Zero();
    for (const Photon& p : photons_) sum += decode_power(p.power, power_scale_);
    return sum;
}

size_t PhotonMap::index_bytes() const {
    if (!index_) return 0;
    return index_->nodes.capacity() * sizeof(Index::Node);
}

size_t PhotonMap::memory_bytes() const { return photons_.size() * sizeof(Photon) + index_bytes(); }

}  // namespace vpm
