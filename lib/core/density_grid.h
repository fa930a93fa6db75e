#pragma once
// vpm's own sparse density grid (no OpenVDB types here; lib/io/vdb_io.cpp converts).
//
// Layout: index space is cut into 8^3 blocks aligned like OpenVDB leaf nodes (block B holds
// voxels [8B, 8B+7]). A dense 3D array of block records covers the data's bounding box; each
// record is either a constant (VDB tile or background) or an index into dense 8^3 float storage
// copied verbatim from a VDB leaf buffer (same x-major order: offset = x<<6 | y<<3 | z).
//
// Lookup is trilinear in index space with voxel centres at integer coordinates (the convention
// of openvdb::tools::BoxSampler); every voxel outside the stored blocks is 0 (background).
//
// Majorants, two levels:
// - Block level: for block B the continuous region [8B, 8B+8)^3 of index space; trilinear
//   interpolation there reads voxels 8B .. 8B+8, and we take the max over voxels 8B-1 .. 8B+8
//   (one-voxel ring on both sides, so points that floating-point error puts just outside their
//   block are still bounded). The block array is padded by one block on the low side so that the
//   region (8*lo-1, 8*lo), where interpolation already sees the first voxel layer, is covered.
//   walk_segments uses the same maxima without the ring (voxels 8B .. 8B+8), since its lookups
//   clamp into the closed block region: ~11% fewer tentative collisions in the plume.
// - Sub-block level, for blocks whose stencil is not constant: 4^3 sub-blocks of 2^3 voxel
//   cells each; sub-block s covers [8B+2s, 8B+2s+2]^3 and its majorant is the max of the 27
//   voxels 8B+2s .. 8B+2s+2 that trilinear interpolation reads there (the trilinear weights are
//   convex, so that max bounds every value in the closed region). No ring: lookups clamp the
//   point into the block's closed region first (density_in), which only undoes rounding of
//   o + t d (the DDA put t in that block). Tracking uses them to thin the block majorant's
//   tentative collisions before any density lookup (majorant_tracking.h), which costs no DDA
//   steps at the sub-block level.
// - Blocks whose own value and all 26 neighbours are one constant c are flagged uniform: the
//   density is exactly c throughout their region, so tracking can use closed forms there.
//
// Exact optical depth: inside one voxel cell [i, i+1]^3 the trilinear field along a line is a
// cubic in the line parameter; stencil() gives the cell's 8 voxels and
// tracking::trilinear_along() (majorant_tracking.h) the cubic in Bernstein form (non-negative
// coefficients when the voxels are), whose integral and its inverse are cheap.
//
// After finalize() the object is immutable: every query is const, allocation-free and thread-safe.
#include <algorithm>
#include <cmath>
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
    // A tighter such box: the union of the regions of blocks with a non-zero majorant, within
    // index_bounds() (empty when the grid is 0 everywhere). walk_segments clips to it first.
    const Bounds3& active_bounds() const { return active_bounds_; }
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
        return data_.size() * sizeof(float) + blocks_.size() * sizeof(Block) + majorant_.size() * sizeof(float) +
               sub_.size() * sizeof(int32_t) + sub_majorant_.size() * sizeof(float);
    }
    // Data box (inclusive voxel indices) given at construction.
    const Vec3i& voxel_lo() const { return voxel_lo_; }
    const Vec3i& voxel_hi() const { return voxel_hi_; }

    // Walks the majorant grid along the index-space line p(t) = o + t d for t in [t0, t1]
    // (t1 may be infinite), calling visit(t_enter, t_exit, majorant) for each block crossed in
    // order; stops early when visit returns false. Blocks with majorant 0 are visited as well
    // (the caller skips them cheaply). Returns the number of blocks visited. (The plain block
    // walk; tracking uses walk_segments. Kept for tests and bench_tracing's baseline tracker.)
    template <class Visit>
    int traverse(const Vec3& o, const Vec3& d, double t0, double t1, Visit&& visit) const;

    // One piece of the majorant walk: the line parameter interval [ta, tb] inside one block, the
    // block's majorant of the density over it, and the block's closed index-space region
    // [lo, lo + 8]^3. uniform: the density is exactly `majorant` there. sub: the block's 64
    // sub-block majorants (null if it has none), for local_majorant().
    struct Segment {
        double ta, tb;
        double majorant;
        bool uniform;
        const float* sub;
        int lo[3];
    };
    // Walks the block majorant grid along o + t d, t in [t0, t1], clipped to active_bounds():
    // blocks with majorant 0 are stepped over without a call. Calls visit(const Segment&) in order
    // of t; stops when it returns false. Returns the number of DDA steps taken.
    template <class Visit>
    int walk_segments(const Vec3& o, const Vec3& d, double t0, double t1, Visit&& visit) const;
    // The same with inv_d = 1 / d per axis given (callers that need it too compute it once).
    template <class Visit>
    int walk_segments(const Vec3& o, const Vec3& d, const Vec3& inv_d, double t0, double t1, Visit&& visit) const;

    // p clamped into the segment's closed block region. The walk put the parameter t in that
    // region; clamping only undoes rounding of o + t d, and keeps lookups under the segment's
    // majorants exactly (sub-block majorants have no ring).
    static Vec3 clamp_to(const Vec3& p, const Segment& s) {
        Vec3 q;
        for (int a = 0; a < 3; ++a) q[a] = std::min(std::max(p[a], double(s.lo[a])), double(s.lo[a] + kDim));
        return q;
    }
    // A majorant of density_in(p, s) at this one point: the majorant of the sub-block holding the
    // clamped p (sub-block s covers [2s, 2s + 2] of the block; on a shared face both bound it).
    double local_majorant(const Vec3& p, const Segment& s) const {
        if (!s.sub) return s.majorant;
        const Vec3 q = clamp_to(p, s);
        int i[3];
        for (int a = 0; a < 3; ++a) i[a] = std::min(static_cast<int>((q[a] - s.lo[a]) * 0.5), 3);
        return s.sub[(i[0] * 4 + i[1]) * 4 + i[2]];
    }
    // density(p) with p first clamped into the segment's closed region. The walk put the
    // parameter t in that region; clamping only undoes rounding of o + t d, and keeps the lookup
    // under the segment's majorant exactly (sub-block majorants have no ring).
    double density_in(const Vec3& p, const Segment& s) const { return density(clamp_to(p, s)); }

    // The 8 voxels of the cell with lower corner (x, y, z), as v[dx*4 + dy*2 + dz] (0 outside).
    void stencil(int x, int y, int z, double v[8]) const {
        if ((x & 7) != 7 && (y & 7) != 7 && (z & 7) != 7) {
            const int bx = (x >> kLog2Dim) - block_lo_.x();
            const int by = (y >> kLog2Dim) - block_lo_.y();
            const int bz = (z >> kLog2Dim) - block_lo_.z();
            if (static_cast<unsigned>(bx) < static_cast<unsigned>(nblocks_.x()) &&
                static_cast<unsigned>(by) < static_cast<unsigned>(nblocks_.y()) &&
                static_cast<unsigned>(bz) < static_cast<unsigned>(nblocks_.z())) {
                const Block& b = blocks_[block_index(bx, by, bz)];
                if (b.dense < 0) {
                    for (int i = 0; i < 8; ++i) v[i] = b.value;
                    return;
                }
                const float* d = data_.data() + static_cast<size_t>(b.dense) * kVoxels + voxel_offset(x, y, z);
                v[0] = d[0], v[1] = d[1], v[2] = d[8], v[3] = d[9];
                v[4] = d[64], v[5] = d[65], v[6] = d[72], v[7] = d[73];
                return;
            }
        }
        for (int i = 0; i < 8; ++i) v[i] = voxel(x + (i >> 2), y + ((i >> 1) & 1), z + (i & 1));
    }

    // The voxels a cell of one block reads (the block and its seven upper neighbours, as pointers
    // to their dense voxels or their constants): stencils of a ray's consecutive cells in that
    // block without a block lookup per voxel (about a third of the cells lie on its upper faces,
    // where stencil() falls back to eight voxel() calls).
    struct BlockWindow {
        const float* dense[8];   // neighbour (dx, dy, dz) in 0..1 at dx*4 + dy*2 + dz; null: constant
        float value[8];          // the constant (0 outside the grid)
    };
    // The window of the block whose lowest voxel is (x, y, z) (multiples of kDim).
    void block_window(int x, int y, int z, BlockWindow& w) const {
        for (int i = 0; i < 8; ++i) {
            const int bx = (x >> kLog2Dim) + (i >> 2) - block_lo_.x();
            const int by = (y >> kLog2Dim) + ((i >> 1) & 1) - block_lo_.y();
            const int bz = (z >> kLog2Dim) + (i & 1) - block_lo_.z();
            w.dense[i] = nullptr;
            w.value[i] = 0.0f;
            if (static_cast<unsigned>(bx) < static_cast<unsigned>(nblocks_.x()) &&
                static_cast<unsigned>(by) < static_cast<unsigned>(nblocks_.y()) &&
                static_cast<unsigned>(bz) < static_cast<unsigned>(nblocks_.z())) {
                const Block& b = blocks_[block_index(bx, by, bz)];
                if (b.dense < 0)
                    w.value[i] = b.value;
                else
                    w.dense[i] = data_.data() + static_cast<size_t>(b.dense) * kVoxels;
            }
        }
    }
    // stencil() of the cell (cx, cy, cz) in 0..7 of a window's block: the same eight values.
    static void stencil(const BlockWindow& w, int cx, int cy, int cz, double v[8]) {
        if (cx != 7 && cy != 7 && cz != 7) {
            if (!w.dense[0]) {
                for (int i = 0; i < 8; ++i) v[i] = w.value[0];
                return;
            }
            const float* d = w.dense[0] + ((cx << 6) | (cy << 3) | cz);
            v[0] = d[0], v[1] = d[1], v[2] = d[8], v[3] = d[9];
            v[4] = d[64], v[5] = d[65], v[6] = d[72], v[7] = d[73];
            return;
        }
        for (int i = 0; i < 8; ++i) {
            const int x = cx + (i >> 2), y = cy + ((i >> 1) & 1), z = cz + (i & 1);
            const int nb = ((x >> kLog2Dim) << 2) | ((y >> kLog2Dim) << 1) | (z >> kLog2Dim);
            v[i] = w.dense[nb] ? w.dense[nb][((x & 7) << 6) | ((y & 7) << 3) | (z & 7)] : w.value[nb];
        }
    }

    // Sub-block majorants: -1 none (block majorant, with ring, holds), -2 uniform block.
    static constexpr int32_t kNoSub = -1, kUniform = -2;
    int32_t sub_index(int bx, int by, int bz) const { return sub_[block_index(bx, by, bz)]; }
    const float* sub_majorants(int32_t sub) const { return sub_majorant_.data() + static_cast<size_t>(sub) * 64; }
    size_t sub_block_count() const { return sub_majorant_.size() / 64; }

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
    // The steps of finalize(), in order.
    void compact_uniform_blocks();
    void find_value_range();
    std::vector<float> block_voxel_maxima() const;
    void find_majorants(const std::vector<float>& own);
    void refine_sub_majorants(size_t i, int bx, int by, int bz);
    void find_walk_majorants();
    void find_active_bounds();

    Vec3i voxel_lo_ = Vec3i::Zero(), voxel_hi_ = Vec3i::Constant(-1);
    Vec3i block_lo_ = Vec3i::Zero();
    Vec3i nblocks_ = Vec3i::Zero();
    std::vector<Block> blocks_;
    std::vector<float> data_;
    std::vector<float> majorant_;
    std::vector<float> walk_majorant_;     // per block: max of the voxels 8B .. 8B+8 (no ring), for walk_segments
    std::vector<int32_t> sub_;             // per block: kNoSub, kUniform, or index into sub_majorant_ / 64
    std::vector<float> sub_majorant_;      // 64 per refined block, sub-block (sx, sy, sz) at (sx*4 + sy)*4 + sz
    Bounds3 index_bounds_;
    Bounds3 active_bounds_;   // the regions of blocks with majorant > 0 (density is 0 outside)
    float max_value_ = 0.0f, min_value_ = 0.0f;
    std::string name_;
    Eigen::Affine3d index_to_world_ = Eigen::Affine3d::Identity();
    int64_t active_voxels_ = 0;
};

// --- inline traversal ------------------------------------------------------------------------
namespace grid_detail {

// 3D DDA over a lattice of n cells per axis, cell width h (a power of two, so the scalings are
// exact), lower corner `base`, along the index-space line o + t d for t in [ta, tb] (the caller
// has clipped [ta, tb] to the lattice). Calls visit(cell, t_enter, t_exit) for consecutive pieces
// covering [ta, tb], in order; returns false as soon as visit does, true when it reached tb.
// inv_d = 1 / d per axis (computed once per ray: the walks nest, and divisions are what a DDA
// setup costs).
template <class Visit>
inline bool dda(const Vec3& o, const Vec3& d, const Vec3& inv_d, const Vec3& base, double h, const Vec3i& n, double ta,
                double tb, Visit&& visit) {
    const double inv_h = 1.0 / h;
    double qo[3], qd[3], inv_qd[3], t_next[3];
    int cell[3], step[3], up[3];   // up: 1 when the next face is the cell's upper one (qd > 0)
    for (int a = 0; a < 3; ++a) {
        qo[a] = (o[a] - base[a]) * inv_h;
        qd[a] = d[a] * inv_h;
        inv_qd[a] = inv_d[a] * h;
        const double q = qo[a] + ta * qd[a];   // entry cell, clamped against rounding
        cell[a] = std::min(std::max(static_cast<int>(std::floor(q)), 0), n[a] - 1);
        // Selects rather than branches on the direction's sign, which is random from ray to ray.
        const int down = qd[a] < 0.0;
        up[a] = qd[a] > 0.0;
        step[a] = up[a] - down;
        const double tn = (cell[a] + up[a] - qo[a]) * inv_qd[a];
        t_next[a] = (up[a] | down) ? tn : kInfinity;
    }
    double t = ta;
    for (;;) {
        const int a = (t_next[0] < t_next[1]) ? (t_next[0] < t_next[2] ? 0 : 2) : (t_next[1] < t_next[2] ? 1 : 2);
        const double t_exit = std::min(std::max(t_next[a], t), tb);
        if (!visit(static_cast<const int*>(cell), t, t_exit)) return false;
        if (t_exit >= tb) return true;
        t = t_exit;
        cell[a] += step[a];
        if (cell[a] < 0 || cell[a] >= n[a]) {
            // [ta, tb] lies inside the lattice, so this is rounding at its last face: the last
            // cell takes the rest up to tb (the pieces always cover [ta, tb] without gaps).
            cell[a] -= step[a];
            t_next[a] = kInfinity;
            continue;
        }
        // Recomputed from the origin each step, so no drift accumulates along long rays.
        t_next[a] = (cell[a] + up[a] - qo[a]) * inv_qd[a];
    }
}

// Clips [t0, t1] of o + t d against the box [lo, hi]; false when nothing is left (or NaN).
inline bool clip_line(const Bounds3& box, const Vec3& o, const Vec3& d, const Vec3& inv_d, double t0, double t1,
                      double& ta, double& tb) {
    ta = t0;
    tb = t1;
    for (int a = 0; a < 3; ++a) {
        const double lo = box.lo[a], hi = box.hi[a];
        if (d[a] == 0.0) {
            if (!(o[a] >= lo && o[a] <= hi)) return false;
            continue;
        }
        const double inv = inv_d[a];
        const double tn = (lo - o[a]) * inv, tf = (hi - o[a]) * inv;
        // "if (tn > tf) swap" as selects (the direction's sign is random, so the branch was not
        // predictable). Same values, NaN included: std::min(tn, tf) is tn unless tf < tn, and
        // std::max(tf, tn) is tf unless tf < tn.
        ta = std::max(ta, std::min(tn, tf));
        tb = std::min(tb, std::max(tf, tn));
    }
    return ta < tb;   // also rejects NaN
}

}  // namespace grid_detail

template <class Visit>
int DensityGrid::walk_segments(const Vec3& o, const Vec3& d, double t0, double t1, Visit&& visit) const {
    return walk_segments(o, d, d.cwiseInverse(), t0, t1, visit);
}

template <class Visit>
int DensityGrid::walk_segments(const Vec3& o, const Vec3& d, const Vec3& inv_d, double t0, double t1, Visit&& visit) const {
    if (blocks_.empty() || active_bounds_.empty()) return 0;
    double ta, tb;
    if (!grid_detail::clip_line(active_bounds_, o, d, inv_d, t0, t1, ta, tb)) return 0;
    int steps = 0;
    const Vec3 base = (block_lo_ * kDim).cast<double>();
    grid_detail::dda(o, d, inv_d, base, double(kDim), nblocks_, ta, tb, [&](const int* c, double a, double b) {
        ++steps;
        const size_t i = block_index(c[0], c[1], c[2]);
        const float m = walk_majorant_[i];
        if (!(m > 0.0f)) return true;
        const int32_t sub = sub_[i];
        Segment s;
        s.ta = a;
        s.tb = b;
        s.majorant = m;
        s.uniform = (sub == kUniform);
        s.sub = sub >= 0 ? sub_majorant_.data() + static_cast<size_t>(sub) * 64 : nullptr;
        s.lo[0] = (block_lo_.x() + c[0]) * kDim;
        s.lo[1] = (block_lo_.y() + c[1]) * kDim;
        s.lo[2] = (block_lo_.z() + c[2]) * kDim;
        return bool(visit(static_cast<const Segment&>(s)));
    });
    return steps;
}

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
