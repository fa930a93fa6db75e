#pragma once
// The photon map: compact photon records (photon.h) plus a kd-tree (nanoflann's node layout and
// split rule), and the walk of every photon.
//
// Stored order: the records are Morton-sorted, the kd-tree is built over them, and then they are
// moved into the tree's leaf order, so that every leaf is one contiguous run of records. The tree
// therefore needs no permutation array (nanoflann's vAcc): the search here reads leaf ranges
// directly, and the 4 bytes per photon that array took hold the photon's walk id instead.
// nanoflann is an implementation detail (pimpl): only photon_map.cpp includes it.
// Queries are const and thread-safe; each thread passes its own NeighbourList, whose buffers are
// reused so that the hot loop allocates nothing once they have grown to k entries.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include "core/math.h"
#include "photon/map/photon.h"

namespace vpm {

struct Neighbour {
    uint32_t index = 0;   // index into the map's stored (Morton-sorted) order
    double d2 = 0.0;      // squared distance to the query, double precision from decoded positions
    Rgb power = Rgb::Zero();
    Vec3 direction = Vec3::UnitZ();   // incoming travel direction
    uint8_t group = 0;                // walk group (photon.h)
    uint32_t walk = 0;                // walk id (PhotonMap::walk)
};

// Result of a kNN query, sorted by (d2, index). Keep one per thread and reuse it.
struct NeighbourList {
    std::vector<Neighbour> items;
    // scratch for the tree search (float distances, uint32 indices)
    std::vector<uint32_t> scratch_index;
    std::vector<float> scratch_d2;
    // scratch for knn_walks: (float d2, index) candidates sorted by distance, a walk set
    std::vector<std::pair<float, uint32_t>> scratch_candidates;
    std::vector<uint32_t> scratch_set;
    // knn_walks' running mean of the photons per walk its queries needed: sizes the first photon
    // gather of the next query; changes the cost of a query, never its result.
    double walk_gather_ratio = 2.0;

    size_t size() const { return items.size(); }
    bool empty() const { return items.empty(); }
    const Neighbour& operator[](size_t i) const { return items[i]; }
    // Distance to the farthest neighbour (0 when empty).
    double max_distance() const { return items.empty() ? 0.0 : std::sqrt(items.back().d2); }
};

class PhotonMap {
public:
    PhotonMap();
    // Builds the map. Photons with non-finite position are rejected with vpm::Error.
    // leaf_size: kd-tree leaf size (nanoflann leaf_max_size).
    explicit PhotonMap(const std::vector<PhotonInput>& photons, size_t leaf_size = 32);
    ~PhotonMap();
    PhotonMap(PhotonMap&&) noexcept;
    PhotonMap& operator=(PhotonMap&&) noexcept;
    PhotonMap(const PhotonMap&) = delete;
    PhotonMap& operator=(const PhotonMap&) = delete;

    size_t size() const { return photons_.size(); }
    bool empty() const { return photons_.empty(); }
    Bounds3 bounds() const { return bounds_; }
    Vec3 centre() const { return centre_; }
    double power_scale() const { return power_scale_; }

    // Decoded attributes of stored photon i (stored order).
    Vec3 position(size_t i) const {
        const Photon& p = photons_[i];
        return centre_ + Vec3(p.p[0], p.p[1], p.p[2]);
    }
    Vec3 direction(size_t i) const { return decode_direction(photons_[i].dir); }
    Rgb power(size_t i) const { return decode_power(photons_[i].power, exponent_scale(photons_[i].reserved)); }
    const Photon& record(size_t i) const { return photons_[i]; }
    // The walk of stored photon i: a dense id in [0, walk_count()), one per distinct
    // PhotonInput::walk label (ids follow the labels' order: a smaller label has a smaller id).
    uint32_t walk(size_t i) const { return walks_[i]; }
    size_t walk_count() const { return walk_count_; }

    // The min(k, available) nearest photons with distance <= max_radius (pass kInfinity for no
    // limit), sorted by distance (ties by stored index). Returns out.size().
    size_t knn(const Vec3& query, size_t k, double max_radius, NeighbourList& out) const;

    // Walk neighbours (photon/estimate/walk_estimate.h): R = the distance at which the k-th distinct
    // walk is first met (its nearest photon). Returns every photon within R (d <= R), sorted by
    // (distance, stored index), so that the k-th walk's nearest photon is the last entry and the
    // photons before it (strictly inside R, up to exact ties) belong to the k - 1 nearer walks.
    // With fewer than k walks within max_radius: every photon within max_radius (sorted), and
    // `walks` < k. Sets walks = the number of distinct walks in the list. Returns out.size().
    size_t knn_walks(const Vec3& query, size_t k, double max_radius, NeighbourList& out, size_t& walks) const;

    // Every photon, in one linear pass without the kd-tree, for a query whose neighbourhood is the
    // whole map (k >= size(), no max_radius: estimator rule (b)). Not sorted: the farthest photon
    // (ties: highest stored index, as knn orders them) is last, the others in stored order. That
    // is all the estimators need there (they sum every photon but the k-th); O(n) instead of the
    // O(n log n) of a sorted gather. Returns out.size().
    size_t gather_all(const Vec3& query, NeighbourList& out) const;

    // Distances below this cannot be resolved by the stored float positions (4 * 2^-24 times
    // the largest half-extent of the bounds); estimators treat them as coincident (rule (c)).
    double position_resolution() const {
        return empty() ? 0.0 : 4.0 * 0x1p-24 * 0.5 * (bounds_.hi - bounds_.lo).cwiseAbs().maxCoeff();
    }

    // Sum of decoded power of all photons (for energy checks).
    Rgb total_power() const;

    // Measured bytes: records + walk ids + kd-tree (nodes and pool slack).
    size_t memory_bytes() const;
    // The kd-tree part of memory_bytes() (its nodes).
    size_t index_bytes() const;

private:
    struct Index;
    template <class ResultSet>
    void search(ResultSet& result, const float q[3]) const;
    // The float search bound for max_radius around the query at `rel` (relative to centre_), with a
    // margin covering the float rounding of stored positions and of the query.
    float search_bound(const Vec3& rel, double max_radius) const;
    // Photon `index` at squared distance d2, decoded.
    Neighbour neighbour(uint32_t index, double d2) const;
    std::vector<Photon> photons_;
    std::vector<uint32_t> walks_;
    size_t walk_count_ = 0;
    Bounds3 bounds_;
    Vec3 centre_ = Vec3::Zero();
    double power_scale_ = 1.0;
    std::unique_ptr<Index> index_;
};

}  // namespace vpm
