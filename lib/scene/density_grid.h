#pragma once
// vpm's own sparse density grid (no OpenVDB types here; lib/scene/vdb_io.cpp converts).
//
// Layout: index space is cut into 8^3 blocks aligned like OpenVDB leaf nodes (block B holds
// voxels [8B, 8B+7]). A dense 3D array of block records covers the data's bounding box; each
// record is either a constant (VDB tile or background) or an index into dense 8^3 float storage
// copied verbatim from a VDB leaf buffer (same x-major order: offset = x<<6 | y<<3 | z).
//
// Lookup is trilinear in index space with voxel centres at integer coordinates (the convention
// of openvdb::tools::BoxSampler); every voxel outside the stored blocks is 0 (background).
//
// Majorant grid: for block B the continuous region [8B, 8B+8)^3 of index space; trilinear
// interpolation there reads voxels 8B .. 8B+8, and we take the max over voxels 8B-1 .. 8B+8
// (one-voxel ring on both sides, so points that floating-point error puts just outside their
// block are still bounded). The block array is padded by one block on the low side so that the
// region (8*lo-1, 8*lo), where interpolation already sees the first voxel layer, is covered.
//
// After finalize() the object is immutable: every query is const, allocation-free and thread-safe.
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "core/math.h"

namespace vpm {

using Vec3i = Eigen::Vector3i;

class DensityGrid {
public:
    static constexpr int kLog2Dim = 3;
    static constexpr int kDim = 8;
    static constexpr int kVoxels = 512;

    DensityGrid() = default;   // empty grid, density 0 everywhere

    // A grid able to hold voxels in the inclusive index box [voxel_lo, voxel_hi], all 0.
    DensityGrid(const Vec3i& voxel_lo, const Vec3i& voxel_hi);

    // Voxel values given densely over [origin, origin + dims): values[(z*dims.y + y)*dims.x + x].
    // Returns a finalized grid.
    static DensityGrid from_dense(const Vec3i& origin, const Vec3i& dims, const std::vector<float>& values);

    // --- construction (before finalize) ---------------------------------------------------------
    // `block` is an absolute block coordinate (voxel >> 3) inside the grid's range.
    void set_block_constant(const Vec3i& block, float value);
    // Makes the block dense (filled with its constant) and returns its 512 values in VDB order.
    // The pointer is valid until the next call that makes a block dense.
    float* dense_block(const Vec3i& block);
    void set_voxel(const Vec3i& ijk, float value);
    // Turns uniform dense blocks into constants, computes the majorant grid and statistics.
    // Must be called before tracking; afterwards the grid is not modified any more.
    void finalize();

    // Metadata carried along from the file.
    void set_name(const std::string& name) { name_ = name; }
    void set_index_to_world(const Eigen::Affine3d& m) { index_to_world_ = m; }
    void set_active_voxel_count(int64_t n) { active_voxels_ = n; }
    const std::string& name() const { return name_; }
    const Eigen::Affine3d& index_to_world() const { return index_to_world_; }
    int64_t active_voxel_count() const { return active_voxels_; }

    // --- queries ------------------------------------------------------------------------------
    bool empty() const { return blocks_.empty(); }
    // Value of voxel ijk (0 outside).
    float voxel(int x, int y, int z) const {
        const int bx = (x >> kLog2Dim) - block_lo_.x();
        const int by = (y >> kLog2Dim) - block_lo_.y();
        const int bz = (z >> kLog2Dim) - block_lo_.z();
        if (static_cast<unsigned>(bx) >= static_cast<unsigned>(nblocks_.x()) ||
            static_cast<unsigned>(by) >= static_cast<unsigned>(nblocks_.y()) ||
            static_cast<unsigned>(bz) >= static_cast<unsigned>(nblocks_.z()))
            return 0.0f;
        const Block& b = blocks_[block_index(bx, by, bz)];
        if (b.dense < 0) return b.value;
        return data_[static_cast<size_t>(b.dense) * kVoxels + voxel_offset(x, y, z)];
    }
    float voxel(const Vec3i& ijk) const { return voxel(ijk.x(), ijk.y(), ijk.z()); }

    // Trilinear density at index-space point p (voxel centres at integer coordinates).
    double density(const Vec3& p) const;

    // Index-space box outside which density() is exactly 0: (data_lo - 1, data_hi + 1).
    const Bounds3& index_bounds() const { return index_bounds_; }
    // Block range of the majorant grid: blocks block_lo() .. block_lo() + block_count() - 1.
    const Vec3i& block_lo() const { return block_lo_; }
    const Vec3i& block_count() const { return nblocks_; }
    // Majorant of block at relative coordinate (0-based in the majorant grid).
    float majorant(int bx, int by, int bz) const { return majorant_[block_index(bx, by, bz)]; }
    float max_density() const { return max_value_; }
    float min_density() const { return min_value_; }
    size_t dense_block_count() const { return data_.size() / kVoxels; }
    size_t block_total() const { return blocks_.size(); }
    size_t memory_bytes() const {
        return data_.size() * sizeof(float) + blocks_.size() * sizeof(Block) + majorant_.size() * sizeof(float);
    }
    // Data box (inclusive voxel indices) given at construction.
    const Vec3i& voxel_lo() const { return voxel_lo_; }
    const Vec3i& voxel_hi() const { return voxel_hi_; }

    // Walks the majorant grid along the index-space line p(t) = o + t d for t in [t0, t1]
    // (t1 may be infinite), calling visit(t_enter, t_exit, majorant) for each block crossed in
    // order; stops early when visit returns false. Blocks with majorant 0 are visited as well
    // (the caller skips them cheaply). Returns the number of blocks visited.
    template <class Visit>
    int traverse(const Vec3& o, const Vec3& d, double t0, double t1, Visit&& visit) const;

private:
    struct Block {
        int32_t dense = -1;   // index into data_ (in blocks of 512), or -1: constant
        float value = 0.0f;   // the constant when dense < 0
    };
    static int voxel_offset(int x, int y, int z) { return ((x & 7) << 6) | ((y & 7) << 3) | (z & 7); }
    size_t block_index(int bx, int by, int bz) const {
        return (static_cast<size_t>(bx) * nblocks_.y() + by) * nblocks_.z() + bz;
    }
    size_t block_index_abs(const Vec3i& block) const;

    Vec3i voxel_lo_ = Vec3i::Zero(), voxel_hi_ = Vec3i::Constant(-1);
    Vec3i block_lo_ = Vec3i::Zero();
    Vec3i nblocks_ = Vec3i::Zero();
    std::vector<Block> blocks_;
    std::vector<float> data_;
    std::vector<float> majorant_;
    Bounds3 index_bounds_;
    float max_value_ = 0.0f, min_value_ = 0.0f;
    std::string name_;
    Eigen::Affine3d index_to_world_ = Eigen::Affine3d::Identity();
    int64_t active_voxels_ = 0;
};

// --- inline traversal ------------------------------------------------------------------------
template <class Visit>
int DensityGrid::traverse(const Vec3& o, const Vec3& d, double t0, double t1, Visit&& visit) const {
    if (blocks_.empty()) return 0;
    // Clip against the data box first (tighter than the padded block range).
    double ta = t0, tb = t1;
    for (int a = 0; a < 3; ++a) {
        const double lo = index_bounds_.lo[a], hi = index_bounds_.hi[a];
        if (d[a] == 0.0) {
            if (!(o[a] >= lo && o[a] <= hi)) return 0;
            continue;
        }
        const double inv = 1.0 / d[a];
        double tn = (lo - o[a]) * inv, tf = (hi - o[a]) * inv;
        if (tn > tf) std::swap(tn, tf);
        ta = std::max(ta, tn);
        tb = std::min(tb, tf);
    }
    if (!(ta < tb)) return 0;   // also rejects NaN

    // Block-space line q(t) = (o + t d)/8 - block_lo.
    Vec3 qo, qd;
    int cell[3], step[3];
    double t_next[3];
    for (int a = 0; a < 3; ++a) {
        qo[a] = o[a] * (1.0 / kDim) - block_lo_[a];
        qd[a] = d[a] * (1.0 / kDim);
        const double q = qo[a] + ta * qd[a];   // entry cell, clamped against rounding
        cell[a] = std::min(std::max(static_cast<int>(std::floor(q)), 0), nblocks_[a] - 1);
        if (qd[a] > 0.0) {
            step[a] = 1;
            t_next[a] = (cell[a] + 1 - qo[a]) / qd[a];
        } else if (qd[a] < 0.0) {
            step[a] = -1;
            t_next[a] = (cell[a] - qo[a]) / qd[a];
        } else {
            step[a] = 0;
            t_next[a] = kInfinity;
        }
    }
    int visited = 0;
    double t = ta;
    for (;;) {
        const int a = (t_next[0] < t_next[1]) ? (t_next[0] < t_next[2] ? 0 : 2) : (t_next[1] < t_next[2] ? 1 : 2);
        const double t_exit = std::min(std::max(t_next[a], t), tb);
        ++visited;
        if (!visit(t, t_exit, majorant_[block_index(cell[0], cell[1], cell[2])])) break;
        if (t_exit >= tb) break;
        t = t_exit;
        cell[a] += step[a];
        if (cell[a] < 0 || cell[a] >= nblocks_[a]) break;
        // Recomputed from the origin each step, so no drift accumulates along long rays.
        t_next[a] = (cell[a] + (step[a] > 0 ? 1 : 0) - qo[a]) / qd[a];
    }
    return visited;
}

}  // namespace vpm
