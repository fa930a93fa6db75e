#include "core/density_grid.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace vpm {

namespace {
int floor_div8(int v) { return v >> 3; }   // arithmetic shift: floor for negatives too
}  // namespace

DensityGrid::DensityGrid(const Vec3i& voxel_lo, const Vec3i& voxel_hi) : voxel_lo_(voxel_lo), voxel_hi_(voxel_hi) {
    if ((voxel_hi.array() < voxel_lo.array()).any()) return;   // empty
    // The block array is flat (16 bytes per block with its majorant and sub-block index): cap it
    // at 2^26 blocks (1 GB), e.g. a 4096 x 4096 x 2048 voxel bounding box.
    constexpr size_t kMaxBlocks = size_t(1) << 26;
    size_t total = 1;
    for (int a = 0; a < 3; ++a) {
        // One padding block below: interpolation at (8*lo - 1, 8*lo) already sees voxel 8*lo.
        block_lo_[a] = floor_div8(voxel_lo[a]) - 1;
        nblocks_[a] = floor_div8(voxel_hi[a]) - block_lo_[a] + 1;
        const size_t n = static_cast<size_t>(nblocks_[a]);
        if (n > kMaxBlocks / total)
            throw std::length_error("DensityGrid: the bounding box spans more than 2^26 blocks of 8^3 voxels");
        total *= n;
    }
    blocks_.assign(total, Block{});
    majorant_.assign(total, 0.0f);
    sub_.assign(total, kNoSub);
    index_bounds_.lo = voxel_lo.cast<double>() - Vec3::Ones();
    index_bounds_.hi = voxel_hi.cast<double>() + Vec3::Ones();
}

DensityGrid DensityGrid::from_dense(const Vec3i& origin, const Vec3i& dims, const std::vector<float>& values) {
    if (static_cast<size_t>(dims.prod()) != values.size())
        throw std::invalid_argument("DensityGrid::from_dense: values.size() != dims product");
    DensityGrid g(origin, origin + dims - Vec3i::Ones());
    for (int z = 0; z < dims.z(); ++z)
        for (int y = 0; y < dims.y(); ++y)
            for (int x = 0; x < dims.x(); ++x) {
                const float v = values[(static_cast<size_t>(z) * dims.y() + y) * dims.x() + x];
                if (v != 0.0f) g.set_voxel(origin + Vec3i(x, y, z), v);
            }
    g.set_active_voxel_count(dims.prod());
    g.finalize();
    return g;
}

size_t DensityGrid::block_index_abs(const Vec3i& block) const {
    const Vec3i r = block - block_lo_;
    for (int a = 0; a < 3; ++a)
        if (r[a] < 0 || r[a] >= nblocks_[a]) throw std::out_of_range("DensityGrid: block outside the grid's range");
    return block_index(r.x(), r.y(), r.z());
}

void DensityGrid::set_block_constant(const Vec3i& block, float value) {
    Block& b = blocks_[block_index_abs(block)];
    if (b.dense >= 0) {
        std::fill_n(data_.begin() + static_cast<ptrdiff_t>(b.dense) * kVoxels, kVoxels, value);
    } else {
        b.value = value;
    }
}

float* DensityGrid::dense_block(const Vec3i& block) {
    Block& b = blocks_[block_index_abs(block)];
    if (b.dense < 0) {
        const size_t n = data_.size() / kVoxels;
        if (n >= static_cast<size_t>(INT32_MAX)) throw std::length_error("DensityGrid: too many dense blocks");
        data_.resize(data_.size() + kVoxels, b.value);
        b.dense = static_cast<int32_t>(n);
    }
    return data_.data() + static_cast<size_t>(b.dense) * kVoxels;
}

void DensityGrid::set_voxel(const Vec3i& ijk, float value) {
    Vec3i block(floor_div8(ijk.x()), floor_div8(ijk.y()), floor_div8(ijk.z()));
    dense_block(block)[voxel_offset(ijk.x(), ijk.y(), ijk.z())] = value;
}

void DensityGrid::finalize() {
    if (blocks_.empty()) return;
    compact_uniform_blocks();
    find_value_range();
    find_majorants(block_voxel_maxima());
    find_walk_majorants();
    find_active_bounds();
}

// Dense blocks holding one value throughout (e.g. all-zero leaves of a simulation's padding)
// become constants: less memory, and lookups there need no data access.
void DensityGrid::compact_uniform_blocks() {
    std::vector<float> kept;
    kept.reserve(data_.size());
    for (Block& b : blocks_) {
        if (b.dense < 0) continue;
        const float* v = data_.data() + static_cast<size_t>(b.dense) * kVoxels;
        bool uniform = true;
        for (int i = 1; i < kVoxels && uniform; ++i) uniform = (v[i] == v[0]);
        if (uniform && std::isfinite(v[0])) {
            b.value = v[0];
            b.dense = -1;
        } else {
            b.dense = static_cast<int32_t>(kept.size() / kVoxels);
            kept.insert(kept.end(), v, v + kVoxels);
        }
    }
    data_.swap(kept);
    data_.shrink_to_fit();
}

void DensityGrid::find_value_range() {
    max_value_ = 0.0f;
    min_value_ = 0.0f;
    bool first = true;
    for (const Block& b : blocks_) {
        if (b.dense >= 0) {
            const float* v = data_.data() + static_cast<size_t>(b.dense) * kVoxels;
            const auto [mn, mx] = std::minmax_element(v, v + kVoxels);
            max_value_ = first ? *mx : std::max(max_value_, *mx);
            min_value_ = first ? *mn : std::min(min_value_, *mn);
        } else {
            max_value_ = first ? b.value : std::max(max_value_, b.value);
            min_value_ = first ? b.value : std::min(min_value_, b.value);
        }
        first = false;
    }
}

// Block maxima of the voxels themselves (find_majorants adds the ring).
std::vector<float> DensityGrid::block_voxel_maxima() const {
    std::vector<float> own(blocks_.size());
    for (size_t i = 0; i < blocks_.size(); ++i) {
        const Block& b = blocks_[i];
        if (b.dense < 0) {
            own[i] = b.value;
        } else {
            const float* v = data_.data() + static_cast<size_t>(b.dense) * kVoxels;
            own[i] = *std::max_element(v, v + kVoxels);
        }
    }
    return own;
}

void DensityGrid::find_majorants(const std::vector<float>& own) {
    for (int bx = 0; bx < nblocks_.x(); ++bx)
        for (int by = 0; by < nblocks_.y(); ++by)
            for (int bz = 0; bz < nblocks_.z(); ++bz) {
                const size_t i = block_index(bx, by, bz);
                // Cheap case: the block and its 26 neighbours are constant -> max of those.
                bool all_const = true, uniform = true;
                float m = own[i];
                for (int dx = -1; dx <= 1 && all_const; ++dx)
                    for (int dy = -1; dy <= 1 && all_const; ++dy)
                        for (int dz = -1; dz <= 1; ++dz) {
                            const int nx = bx + dx, ny = by + dy, nz = bz + dz;
                            if (nx < 0 || ny < 0 || nz < 0 || nx >= nblocks_.x() || ny >= nblocks_.y() ||
                                nz >= nblocks_.z()) {
                                uniform = uniform && own[i] == 0.0f;
                                continue;   // background 0 outside; majorants are >= 0 anyway
                            }
                            const Block& nb = blocks_[block_index(nx, ny, nz)];
                            if (nb.dense >= 0) { all_const = false; break; }
                            m = std::max(m, nb.value);
                            uniform = uniform && nb.value == own[i];
                        }
                if (!all_const) {
                    // Exact max over voxels 8B-1 .. 8B+8 in each axis.
                    const int x0 = (block_lo_.x() + bx) * kDim - 1;
                    const int y0 = (block_lo_.y() + by) * kDim - 1;
                    const int z0 = (block_lo_.z() + bz) * kDim - 1;
                    m = own[i];
                    for (int x = x0; x < x0 + kDim + 2; ++x)
                        for (int y = y0; y < y0 + kDim + 2; ++y)
                            for (int z = z0; z < z0 + kDim + 2; ++z) m = std::max(m, voxel(x, y, z));
                }
                // Trilinear weights are convex, so the max voxel bounds every interpolated value;
                // clamp below at 0 (negative densities are rejected by the loader anyway).
                majorant_[i] = std::max(m, 0.0f);
                if (all_const && uniform && majorant_[i] > 0.0f) sub_[i] = kUniform;
                if (all_const || !(majorant_[i] > 0.0f)) continue;
                refine_sub_majorants(i, bx, by, bz);
            }
    sub_majorant_.shrink_to_fit();
}

// Sub-block level: max of the 27 voxels each 2^3-cell sub-block's trilinear stencil reads (the
// point is clamped into the closed sub-block, see density_in).
void DensityGrid::refine_sub_majorants(size_t i, int bx, int by, int bz) {
    const int x0 = (block_lo_.x() + bx) * kDim, y0 = (block_lo_.y() + by) * kDim, z0 = (block_lo_.z() + bz) * kDim;
    float vox[kDim + 1][kDim + 1][kDim + 1];
    for (int x = 0; x <= kDim; ++x)
        for (int y = 0; y <= kDim; ++y)
            for (int z = 0; z <= kDim; ++z) vox[x][y][z] = voxel(x0 + x, y0 + y, z0 + z);
    if (sub_majorant_.size() / 64 >= static_cast<size_t>(INT32_MAX))
        throw std::length_error("DensityGrid: too many refined blocks");
    sub_[i] = static_cast<int32_t>(sub_majorant_.size() / 64);
    for (int sx = 0; sx < 4; ++sx)
        for (int sy = 0; sy < 4; ++sy)
            for (int sz = 0; sz < 4; ++sz) {
                float sm = 0.0f;
                for (int x = 2 * sx; x <= 2 * sx + 2; ++x)
                    for (int y = 2 * sy; y <= 2 * sy + 2; ++y)
                        for (int z = 2 * sz; z <= 2 * sz + 2; ++z) sm = std::max(sm, vox[x][y][z]);
                sub_majorant_.push_back(sm);
            }
}

// The walk's majorants: max over the voxels 8B .. 8B+8 that interpolation reads inside the closed
// block region (no ring: walk_segments' lookups clamp into that region).
void DensityGrid::find_walk_majorants() {
    walk_majorant_.assign(blocks_.size(), 0.0f);
    for (int bx = 0; bx < nblocks_.x(); ++bx)
        for (int by = 0; by < nblocks_.y(); ++by)
            for (int bz = 0; bz < nblocks_.z(); ++bz) {
                const size_t i = block_index(bx, by, bz);
                if (!(majorant_[i] > 0.0f)) continue;
                float m = 0.0f;
                if (sub_[i] >= 0) {
                    const float* sm = sub_majorants(sub_[i]);
                    m = *std::max_element(sm, sm + 64);
                } else {   // the block and its neighbours are constants (see find_majorants)
                    for (int dx = 0; dx <= 1; ++dx)
                        for (int dy = 0; dy <= 1; ++dy)
                            for (int dz = 0; dz <= 1; ++dz) {
                                const int nx = bx + dx, ny = by + dy, nz = bz + dz;
                                if (nx >= nblocks_.x() || ny >= nblocks_.y() || nz >= nblocks_.z()) continue;
                                m = std::max(m, blocks_[block_index(nx, ny, nz)].value);
                            }
                }
                walk_majorant_[i] = std::max(m, 0.0f);
            }
}

// The index box of the blocks with a non-zero walk majorant, within the grid's index bounds.
void DensityGrid::find_active_bounds() {
    active_bounds_ = Bounds3{};
    for (int bx = 0; bx < nblocks_.x(); ++bx)
        for (int by = 0; by < nblocks_.y(); ++by)
            for (int bz = 0; bz < nblocks_.z(); ++bz)
                if (walk_majorant_[block_index(bx, by, bz)] > 0.0f) {
                    const Vec3 lo = ((block_lo_ + Vec3i(bx, by, bz)) * kDim).cast<double>();
                    active_bounds_.extend(lo);
                    active_bounds_.extend(lo + Vec3::Constant(kDim));
                }
    if (!active_bounds_.empty()) {
        active_bounds_.lo = active_bounds_.lo.cwiseMax(index_bounds_.lo);
        active_bounds_.hi = active_bounds_.hi.cwiseMin(index_bounds_.hi);
    }
}

double DensityGrid::density(const Vec3& p) const {
    // NaN-safe range test; outside (lo-1, hi+1) every voxel read is background.
    if (!(p.x() > index_bounds_.lo.x() && p.x() < index_bounds_.hi.x() && p.y() > index_bounds_.lo.y() &&
          p.y() < index_bounds_.hi.y() && p.z() > index_bounds_.lo.z() && p.z() < index_bounds_.hi.z()))
        return 0.0;
    const double fx = std::floor(p.x()), fy = std::floor(p.y()), fz = std::floor(p.z());
    const int ix = static_cast<int>(fx), iy = static_cast<int>(fy), iz = static_cast<int>(fz);
    const double wx = p.x() - fx, wy = p.y() - fy, wz = p.z() - fz;
    double v[2][2][2];   // double: differences of floats would round in float
    if ((ix & 7) != 7 && (iy & 7) != 7 && (iz & 7) != 7) {
        // All eight corners in one block: one block lookup.
        const int bx = (ix >> kLog2Dim) - block_lo_.x();
        const int by = (iy >> kLog2Dim) - block_lo_.y();
        const int bz = (iz >> kLog2Dim) - block_lo_.z();
        const Block& b = blocks_[block_index(bx, by, bz)];
        if (b.dense < 0) return b.value;
        const float* d = data_.data() + static_cast<size_t>(b.dense) * kVoxels + voxel_offset(ix, iy, iz);
        v[0][0][0] = d[0];
        v[0][0][1] = d[1];
        v[0][1][0] = d[8];
        v[0][1][1] = d[9];
        v[1][0][0] = d[64];
        v[1][0][1] = d[65];
        v[1][1][0] = d[72];
        v[1][1][1] = d[73];
    } else {
        for (int dx = 0; dx < 2; ++dx)
            for (int dy = 0; dy < 2; ++dy)
                for (int dz = 0; dz < 2; ++dz) v[dx][dy][dz] = voxel(ix + dx, iy + dy, iz + dz);
    }
    // Same order as openvdb BoxSampler: z, then y, then x.
    const double a00 = v[0][0][0] + wz * (v[0][0][1] - v[0][0][0]);
    const double a01 = v[0][1][0] + wz * (v[0][1][1] - v[0][1][0]);
    const double a10 = v[1][0][0] + wz * (v[1][0][1] - v[1][0][0]);
    const double a11 = v[1][1][0] + wz * (v[1][1][1] - v[1][1][0]);
    const double b0 = a00 + wy * (a01 - a00);
    const double b1 = a10 + wy * (a11 - a10);
    return b0 + wx * (b1 - b0);
}

}  // namespace vpm
