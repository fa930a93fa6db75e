#include "photon/map/photon_map.h"

#include "core/morton.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <nanoflann.hpp>
#include <numeric>
#include <string>
#include <utility>

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <tbb/parallel_sort.h>

#include "core/error.h"
#include "photon/map/walk_set.h"

namespace vpm {

namespace {

// nanoflann dataset adaptor over the compact records (float positions relative to the centre).
struct RecordAdaptor {
    const Photon* data = nullptr;
    size_t n = 0;
    size_t kdtree_get_point_count() const { return n; }
    float kdtree_get_pt(uint32_t i, size_t d) const { return data[i].p[d]; }
    template <class BBox>
    bool kdtree_get_bbox(BBox&) const { return false; }
};

using Metric = nanoflann::L2_Simple_Adaptor<float, RecordAdaptor, float, uint32_t>;
using Tree = nanoflann::KDTreeSingleIndexAdaptor<Metric, RecordAdaptor, 3, uint32_t>;

// k nearest with an upper bound on the squared distance: the tree prunes with
// min(current k-th distance, radius^2), so a small max_radius makes queries cheaper.
// Small k: a sorted array with insertion (fastest for the usual k <= 64). Large k: a binary
// max-heap on the distance, O(log k) per insertion instead of O(k) (with k in the tens of
// thousands the insertion sort made one query cost O(n k)). Either way the caller sorts the
// found entries; only the set matters here.
class KnnRadiusResultSet {
public:
    using DistanceType = float;
    using IndexType = uint32_t;
    static constexpr size_t kHeapFrom = 128;
    KnnRadiusResultSet(uint32_t* idx, float* d2, size_t capacity, float radius2)
        : idx_(idx), d2_(d2), cap_(capacity), radius2_(radius2), heap_(capacity >= kHeapFrom) {}
    size_t size() const { return count_; }
    bool full() const { return count_ == cap_; }
    float worstDist() const {
        if (count_ < cap_) return radius2_;
        return heap_ ? d2_[0] : d2_[cap_ - 1];
    }
    bool addPoint(float dist, uint32_t index) {
        if (dist >= worstDist()) return true;
        if (heap_) {
            if (count_ < cap_) {
                sift_up(count_, dist, index);
                ++count_;
            } else {
                sift_down(dist, index);   // replaces the current farthest at the root
            }
            return true;
        }
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
    // Max-heap on (d2, index): larger index wins ties, so the kept set is deterministic.
    bool greater(float da, uint32_t ia, float db, uint32_t ib) const { return da > db || (da == db && ia > ib); }
    void sift_up(size_t i, float dist, uint32_t index) {
        while (i > 0) {
            const size_t parent = (i - 1) / 2;
            if (!greater(dist, index, d2_[parent], idx_[parent])) break;
            d2_[i] = d2_[parent];
            idx_[i] = idx_[parent];
            i = parent;
        }
        d2_[i] = dist;
        idx_[i] = index;
    }
    void sift_down(float dist, uint32_t index) {
        size_t i = 0;
        for (;;) {
            size_t child = 2 * i + 1;
            if (child >= count_) break;
            if (child + 1 < count_ && greater(d2_[child + 1], idx_[child + 1], d2_[child], idx_[child])) ++child;
            if (!greater(d2_[child], idx_[child], dist, index)) break;
            d2_[i] = d2_[child];
            idx_[i] = idx_[child];
            i = child;
        }
        d2_[i] = dist;
        idx_[i] = index;
    }
    uint32_t* idx_;
    float* d2_;
    size_t cap_;
    size_t count_ = 0;
    float radius2_;
    bool heap_;
};

}  // namespace

// nanoflann 1.4's buildIndex is serial. This builds the same tree (nanoflann's own middleSplit_,
// node layout and leaf boxes, so queries visit the same nodes) with the two halves of every split
// of more than kParallelFrom points built as parallel tasks; nodes come from per-thread pools
// that live as long as the tree. Which thread builds a node changes nothing in it: the tree is the
// same on any thread count.
struct PhotonMap::Index {
    RecordAdaptor adaptor;
    Tree tree;
    tbb::enumerable_thread_specific<nanoflann::PooledAllocator> pools;
    static constexpr size_t kParallelFrom = 1 << 15;

    Index(const Photon* data, size_t n, size_t leaf)
        : adaptor{data, n},
          tree(3, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(leaf, nanoflann::KDTreeSingleIndexAdaptorFlags::SkipInitialBuildIndex)) {
        tree.vAcc.resize(n);
        tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 1 << 16), [&](const tbb::blocked_range<size_t>& r) {
            for (size_t i = r.begin(); i < r.end(); ++i) tree.vAcc[i] = uint32_t(i);
        });
        tree.m_size = tree.m_size_at_index_build = n;
        if (n == 0) return;
        for (int a = 0; a < 3; ++a) tree.root_bbox[size_t(a)].low = tree.root_bbox[size_t(a)].high = data[0].p[a];
        for (size_t i = 1; i < n; ++i)
            for (int a = 0; a < 3; ++a) {
                tree.root_bbox[size_t(a)].low = std::min(tree.root_bbox[size_t(a)].low, data[i].p[a]);
                tree.root_bbox[size_t(a)].high = std::max(tree.root_bbox[size_t(a)].high, data[i].p[a]);
            }
        tree.root_node = divide(0, n, tree.root_bbox);
    }

    // nanoflann's divideTree, with the pool per thread and the halves of large nodes in parallel.
    Tree::NodePtr divide(size_t left, size_t right, Tree::BoundingBox& bbox) {
        Tree::NodePtr node = pools.local().allocate<Tree::Node>();
        if (right - left <= tree.m_leaf_max_size) {
            node->child1 = node->child2 = nullptr;
            node->node_type.lr.left = left;
            node->node_type.lr.right = right;
            for (int a = 0; a < 3; ++a) bbox[size_t(a)].low = bbox[size_t(a)].high = adaptor.kdtree_get_pt(tree.vAcc[left], size_t(a));
            for (size_t k = left + 1; k < right; ++k)
                for (int a = 0; a < 3; ++a) {
                    const float v = adaptor.kdtree_get_pt(tree.vAcc[k], size_t(a));
                    if (bbox[size_t(a)].low > v) bbox[size_t(a)].low = v;
                    if (bbox[size_t(a)].high < v) bbox[size_t(a)].high = v;
                }
            return node;
        }
        Tree::Offset idx;
        Tree::Dimension cutfeat;
        float cutval;
        tree.middleSplit_(tree, left, right - left, idx, cutfeat, cutval, bbox);
        node->node_type.sub.divfeat = cutfeat;
        Tree::BoundingBox left_bbox(bbox), right_bbox(bbox);
        left_bbox[size_t(cutfeat)].high = cutval;
        right_bbox[size_t(cutfeat)].low = cutval;
        if (right - left >= kParallelFrom) {
            tbb::parallel_invoke([&] { node->child1 = divide(left, left + idx, left_bbox); },
                                 [&] { node->child2 = divide(left + idx, right, right_bbox); });
        } else {
            node->child1 = divide(left, left + idx, left_bbox);
            node->child2 = divide(left + idx, right, right_bbox);
        }
        node->node_type.sub.divlow = left_bbox[size_t(cutfeat)].high;
        node->node_type.sub.divhigh = right_bbox[size_t(cutfeat)].low;
        for (int a = 0; a < 3; ++a) {
            bbox[size_t(a)].low = std::min(left_bbox[size_t(a)].low, right_bbox[size_t(a)].low);
            bbox[size_t(a)].high = std::max(left_bbox[size_t(a)].high, right_bbox[size_t(a)].high);
        }
        return node;
    }

    // Once the records are in leaf order (leaf range [left, right) = records left..right-1) the
    // permutation array is redundant: freed.
    void release_order(const Photon* data) {
        std::vector<uint32_t>().swap(tree.vAcc);
        adaptor.data = data;
    }

    size_t bytes() const {
        size_t b = tree.vAcc.size() * sizeof(uint32_t);
        for (const auto& p : pools) b += p.usedMemory + p.wastedMemory;
        return b;
    }
};

namespace {

// Dense walk ids, in input order, for the labels PhotonInput::walk: ids follow the labels' order.
// The tracer's labels never decrease along its output (one walk's photons are consecutive), which
// takes one linear pass; any other order sorts the distinct labels. Returns the number of walks.
size_t dense_walk_ids(const std::vector<PhotonInput>& in, std::vector<uint32_t>& ids) {
    ids.resize(in.size());
    if (in.empty()) return 0;
    bool sorted = true;
    for (size_t i = 1; i < in.size() && sorted; ++i) sorted = in[i - 1].walk <= in[i].walk;
    if (sorted) {
        uint32_t id = 0;
        ids[0] = 0;
        for (size_t i = 1; i < in.size(); ++i) ids[i] = in[i].walk == in[i - 1].walk ? id : ++id;
        return size_t(id) + 1;
    }
    std::vector<uint64_t> labels(in.size());
    for (size_t i = 0; i < in.size(); ++i) labels[i] = in[i].walk;
    tbb::parallel_sort(labels.begin(), labels.end());
    labels.erase(std::unique(labels.begin(), labels.end()), labels.end());
    tbb::parallel_for(tbb::blocked_range<size_t>(0, in.size(), 1 << 14), [&](const tbb::blocked_range<size_t>& r) {
        for (size_t i = r.begin(); i < r.end(); ++i)
            ids[i] = uint32_t(std::lower_bound(labels.begin(), labels.end(), in[i].walk) - labels.begin());
    });
    return labels.size();
}

// nanoflann's searchLevel over leaf ranges that are record ranges (no permutation array), with
// nanoflann's float metric (L2_Simple_Adaptor) and its pruning (eps = 0).
template <class ResultSet, class NodePtr>
void search_level(ResultSet& rs, const Photon* data, const float* q, NodePtr node, float mindist, float* dists) {
    if (!node->child1 && !node->child2) {
        const float worst = rs.worstDist();
        for (size_t i = node->node_type.lr.left; i < node->node_type.lr.right; ++i) {
            const float* p = data[i].p;
            float d = 0.0f;
            for (int a = 0; a < 3; ++a) {
                const float diff = q[a] - p[a];
                d += diff * diff;
            }
            if (d < worst) rs.addPoint(d, uint32_t(i));
        }
        return;
    }
    const int axis = int(node->node_type.sub.divfeat);
    const float v = q[axis];
    const float diff1 = v - node->node_type.sub.divlow, diff2 = v - node->node_type.sub.divhigh;
    NodePtr best, other;
    float cut;
    if (diff1 + diff2 < 0) {
        best = node->child1;
        other = node->child2;
        cut = (v - node->node_type.sub.divhigh) * (v - node->node_type.sub.divhigh);
    } else {
        best = node->child2;
        other = node->child1;
        cut = (v - node->node_type.sub.divlow) * (v - node->node_type.sub.divlow);
    }
    search_level(rs, data, q, best, mindist, dists);
    const float saved = dists[axis];
    mindist = mindist + cut - saved;
    dists[axis] = cut;
    if (mindist <= rs.worstDist()) search_level(rs, data, q, other, mindist, dists);
    dists[axis] = saved;
}

}  // namespace

template <class ResultSet>
void PhotonMap::search(ResultSet& rs, const float q[3]) const {
    const Tree& tree = index_->tree;
    float dists[3] = {0.0f, 0.0f, 0.0f};
    float mindist = 0.0f;
    for (int a = 0; a < 3; ++a) {   // nanoflann's computeInitialDistances
        if (q[a] < tree.root_bbox[size_t(a)].low) {
            dists[a] = (q[a] - tree.root_bbox[size_t(a)].low) * (q[a] - tree.root_bbox[size_t(a)].low);
            mindist += dists[a];
        }
        if (q[a] > tree.root_bbox[size_t(a)].high) {
            dists[a] = (q[a] - tree.root_bbox[size_t(a)].high) * (q[a] - tree.root_bbox[size_t(a)].high);
            mindist += dists[a];
        }
    }
    search_level(rs, photons_.data(), q, tree.root_node, mindist, dists);
}

PhotonMap::PhotonMap() = default;
PhotonMap::~PhotonMap() = default;
PhotonMap::PhotonMap(PhotonMap&&) noexcept = default;
PhotonMap& PhotonMap::operator=(PhotonMap&&) noexcept = default;

PhotonMap::PhotonMap(const std::vector<PhotonInput>& in, size_t leaf_size) {
    if (leaf_size < 1) throw Error("photon map: leaf_size must be at least 1, got 0");
    if (in.size() >= std::numeric_limits<uint32_t>::max())
        throw Error("photon map: too many photons (" + std::to_string(in.size()) + ", max 2^32-2)");
    double max_power = 0.0;
    for (size_t i = 0; i < in.size(); ++i) {
        const PhotonInput& p = in[i];
        if (!p.position.allFinite())
            throw Error("photon map: photon " + std::to_string(i) + " has a non-finite position");
        if (!all_finite(p.power))
            throw Error("photon map: photon " + std::to_string(i) + " has non-finite power");
        if ((p.power.array() < 0.0).any())
            throw Error("photon map: photon " + std::to_string(i) + " has negative power (powers are stored as non-negative)");
        bounds_.extend(p.position);
        max_power = std::max(max_power, p.power.maxCoeff());
    }
    if (in.empty()) return;
    centre_ = 0.5 * (bounds_.lo + bounds_.hi);
    power_scale_ = max_power > 0.0 ? max_power : 1.0;

    // Morton order over the bounds for cache coherence of leaves and of neighbouring queries.
    const Vec3 extent = (bounds_.hi - bounds_.lo).cwiseMax(Vec3::Constant(1e-300));
    // Keys (code, index) are distinct, so the parallel sort gives the one sorted order.
    std::vector<std::pair<uint64_t, uint32_t>> keys(in.size());
    const tbb::blocked_range<size_t> all(0, in.size(), 1 << 14);
    tbb::parallel_for(all, [&](const tbb::blocked_range<size_t>& range) {
        for (size_t i = range.begin(); i < range.end(); ++i) {
            keys[i] = {morton_code(in[i].position, bounds_.lo, extent), static_cast<uint32_t>(i)};
        }
    });
    tbb::parallel_sort(keys.begin(), keys.end());

    std::vector<uint32_t> morton_walks;   // walk id per Morton-ordered record
    {
        std::vector<uint32_t> ids;
        walk_count_ = dense_walk_ids(in, ids);
        morton_walks.resize(in.size());
        photons_.resize(in.size());
        tbb::parallel_for(all, [&](const tbb::blocked_range<size_t>& range) {
            for (size_t j = range.begin(); j < range.end(); ++j) {
                const PhotonInput& p = in[keys[j].second];
                Photon& r = photons_[j];
                const Vec3 rel = p.position - centre_;
                for (int a = 0; a < 3; ++a) r.p[a] = static_cast<float>(rel[a]);
                encode_direction(p.direction, r.dir);
                const int16_t e = power_exponent(p.power);   // per photon: any dynamic range in one map
                encode_power(p.power, std::ldexp(1.0, -e), r.power);
                r.reserved = exponent_bits(e, p.group);
                morton_walks[j] = ids[keys[j].second];
            }
        });
    }
    std::vector<std::pair<uint64_t, uint32_t>>().swap(keys);
    index_ = std::make_unique<Index>(photons_.data(), photons_.size(), leaf_size);
    // The records into the tree's leaf order; the permutation array goes, the walk ids take its place.
    const std::vector<uint32_t>& order = index_->tree.vAcc;
    std::vector<Photon> leaf_order(photons_.size());
    walks_.resize(photons_.size());
    tbb::parallel_for(all, [&](const tbb::blocked_range<size_t>& range) {
        for (size_t j = range.begin(); j < range.end(); ++j) {
            leaf_order[j] = photons_[order[j]];
            walks_[j] = morton_walks[order[j]];
        }
    });
    photons_.swap(leaf_order);
    index_->release_order(photons_.data());
}

float PhotonMap::search_bound(const Vec3& rel, double max_radius) const {
    if (!std::isfinite(max_radius)) return std::numeric_limits<float>::max();
    // Each float rounding is <= 2^-24 of the coordinate magnitude per axis.
    const double coord = rel.cwiseAbs().maxCoeff() + 0.5 * (bounds_.hi - bounds_.lo).cwiseAbs().maxCoeff();
    const double slack = 8.0 * 0x1p-24 * coord;
    return static_cast<float>((max_radius + slack) * (max_radius + slack) * (1.0 + 1e-6));
}

Neighbour PhotonMap::neighbour(uint32_t index, double d2) const {
    const Photon& p = photons_[index];
    Neighbour n;
    n.index = index;
    n.d2 = d2;
    n.power = decode_power(p.power, exponent_scale(p.reserved));
    n.direction = decode_direction(p.dir);
    n.group = walk_group(p.reserved);
    n.walk = walks_[index];
    return n;
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
    // The exact double test is applied below.
    KnnRadiusResultSet rs(out.scratch_index.data(), out.scratch_d2.data(), k, search_bound(rel, max_radius));
    search(rs, q);
    const size_t found = rs.size();
    if (out.items.capacity() < k) out.items.reserve(k);
    for (size_t i = 0; i < found; ++i) {
        const uint32_t idx = out.scratch_index[i];
        const Photon& p = photons_[idx];
        const Vec3 d = rel - Vec3(p.p[0], p.p[1], p.p[2]);
        const double d2 = d.squaredNorm();
        if (limited && d2 > max_r2) continue;
        out.items.push_back(neighbour(idx, d2));
    }
    std::sort(out.items.begin(), out.items.end(), [](const Neighbour& a, const Neighbour& b) {
        return a.d2 < b.d2 || (a.d2 == b.d2 && a.index < b.index);
    });
    return out.items.size();
}

size_t PhotonMap::knn_walks(const Vec3& query, size_t k, double max_radius, NeighbourList& out, size_t& walks) const {
    out.items.clear();
    walks = 0;
    if (k == 0 || photons_.empty() || !(max_radius >= 0.0)) return 0;
    const Vec3 rel = query - centre_;
    const float q[3] = {static_cast<float>(rel[0]), static_cast<float>(rel[1]), static_cast<float>(rel[2])};
    const bool limited = std::isfinite(max_radius);
    const double max_r2 = max_radius * max_radius;
    const float bound = search_bound(rel, max_radius);
    // The m nearest photons (float distances); they hold the walk neighbourhood when its k-th walk is
    // met strictly before the m-th photon (every photon at or inside R is then among them), or when
    // they are every photon within the bound; otherwise m grows by half and the search runs again.
    // m is the photons per walk the earlier queries of this list needed (a running mean) times k,
    // plus about 2.5 standard deviations of a Poisson count of the siblings, so that one search
    // mostly suffices (docs/walk_correlation.md, Cost). R (float) is the k-th smallest of the walks'
    // nearest-photon distances: the same whatever order ties come in, so m changes the cost, never
    // the result.
    auto& cand = out.scratch_candidates;
    const double expected = double(k) * out.walk_gather_ratio;
    size_t m = std::min(photons_.size(),
                        std::max(k + 1, size_t(std::ceil(expected + 1.0 + 2.5 * std::sqrt(expected - double(k) + 1.0)))));
    float r_walk = bound;
    size_t inside = 0;   // candidates with d <= r_walk
    for (;;) {
        if (out.scratch_index.size() < m) {
            out.scratch_index.resize(m);
            out.scratch_d2.resize(m);
        }
        KnnRadiusResultSet rs(out.scratch_index.data(), out.scratch_d2.data(), m, bound);
        search(rs, q);
        const size_t found = rs.size();
        cand.resize(found);
        for (size_t i = 0; i < found; ++i) cand[i] = {out.scratch_d2[i], out.scratch_index[i]};
        if (m >= KnnRadiusResultSet::kHeapFrom) std::sort(cand.begin(), cand.end());   // a heap, not sorted
        const bool all_within_bound = found < m || m == photons_.size();
        size_t seen = 0;
        WalkSet set(out.scratch_set, found);
        size_t i = 0;
        for (; i < found; ++i)
            if (set.insert(walks_[cand[i].second]) && ++seen == k) break;
        if (seen == k && (all_within_bound || cand[i].first < cand[found - 1].first)) {
            r_walk = cand[i].first;
            inside = i + 1;
            while (inside < found && cand[inside].first <= r_walk) ++inside;
            break;
        }
        if (all_within_bound) {   // fewer than k walks within the bound: every photon found
            inside = found;
            break;
        }
        m = std::min(photons_.size(), m + m / 2 + 1);
    }
    out.walk_gather_ratio = 0.9 * out.walk_gather_ratio + 0.1 * std::max(1.0, double(inside) / double(k));
    for (size_t i = 0; i < inside; ++i) {
        const uint32_t idx = cand[i].second;
        const Photon& p = photons_[idx];
        const double d2 = (rel - Vec3(p.p[0], p.p[1], p.p[2])).squaredNorm();
        if (limited && d2 > max_r2) continue;
        out.items.push_back(neighbour(idx, d2));
    }
    std::sort(out.items.begin(), out.items.end(), [](const Neighbour& a, const Neighbour& b) {
        return a.d2 < b.d2 || (a.d2 == b.d2 && a.index < b.index);
    });
    // In double precision: the list ends at the first photon of the k-th distinct walk.
    const size_t end = walk_neighbourhood_size(out.items.size(), k, [&](size_t i) { return out.items[i].walk; },
                                               out.scratch_set, walks);
    out.items.resize(end);
    return end;
}

size_t PhotonMap::gather_all(const Vec3& query, NeighbourList& out) const {
    out.items.clear();
    if (photons_.empty()) return 0;
    if (out.items.capacity() < photons_.size()) out.items.reserve(photons_.size());
    const Vec3 rel = query - centre_;
    size_t far = 0;
    for (size_t i = 0; i < photons_.size(); ++i) {
        const Photon& p = photons_[i];
        const Neighbour n = neighbour(uint32_t(i), (rel - Vec3(p.p[0], p.p[1], p.p[2])).squaredNorm());
        if (i == 0 || n.d2 >= out.items[far].d2) far = i;   // ties: the highest index is "farthest"
        out.items.push_back(n);
    }
    std::swap(out.items[far], out.items.back());
    return out.items.size();
}

Rgb PhotonMap::total_power() const {
    Rgb sum = Rgb::Zero();
    for (const Photon& p : photons_) sum += decode_power(p.power, exponent_scale(p.reserved));
    return sum;
}

size_t PhotonMap::index_bytes() const {
    if (!index_) return 0;
    return index_->bytes();
}

size_t PhotonMap::memory_bytes() const {
    return photons_.size() * sizeof(Photon) + walks_.size() * sizeof(uint32_t) + index_bytes();
}

}  // namespace vpm
