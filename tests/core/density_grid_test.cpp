// DensityGrid: trilinear lookup against a brute-force reference, majorant bounds.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "core/sampling/rng.h"
#include "core/density_grid.h"

using namespace vpm;

namespace {

struct DenseRef {
    Vec3i origin, dims;
    std::vector<float> v;
    float at(int x, int y, int z) const {
        x -= origin.x();
        y -= origin.y();
        z -= origin.z();
        if (x < 0 || y < 0 || z < 0 || x >= dims.x() || y >= dims.y() || z >= dims.z()) return 0.0f;
        return v[(size_t(z) * dims.y() + y) * dims.x() + x];
    }
    // Plain weighted sum of the 8 corners (a different formula from the lerp cascade).
    double trilinear(const Vec3& p) const {
        const int ix = int(std::floor(p.x())), iy = int(std::floor(p.y())), iz = int(std::floor(p.z()));
        const double fx = p.x() - ix, fy = p.y() - iy, fz = p.z() - iz;
        double s = 0;
        for (int c = 0; c < 8; ++c) {
            const int dx = c & 1, dy = (c >> 1) & 1, dz = (c >> 2) & 1;
            s += (dx ? fx : 1 - fx) * (dy ? fy : 1 - fy) * (dz ? fz : 1 - fz) * at(ix + dx, iy + dy, iz + dz);
        }
        return s;
    }
};

// Random grid with zero regions, constant patches and a few spikes, at a non-aligned origin.
DenseRef random_ref(uint64_t seed) {
    DenseRef r;
    r.origin = Vec3i(-13, 5, -22);
    r.dims = Vec3i(37, 21, 44);
    Rng rng(seed);
    r.v.resize(size_t(r.dims.prod()));
    for (int z = 0; z < r.dims.z(); ++z)
        for (int y = 0; y < r.dims.y(); ++y)
            for (int x = 0; x < r.dims.x(); ++x) {
                float val;
                if (x < 9) val = 0.0f;                                  // empty slab
                else if (y < 6) val = 0.25f;                            // constant slab
                else val = static_cast<float>(rng.uniform() * 2.0);     // noise
                if (rng.uniform() < 0.002) val = 50.0f;                 // spikes
                r.v[(size_t(z) * r.dims.y() + y) * r.dims.x() + x] = val;
            }
    return r;
}

Vec3 random_point(Rng& rng, const Vec3& lo, const Vec3& hi) {
    return Vec3(lo.x() + rng.uniform() * (hi.x() - lo.x()), lo.y() + rng.uniform() * (hi.y() - lo.y()),
                lo.z() + rng.uniform() * (hi.z() - lo.z()));
}

float majorant_at(const DensityGrid& g, const Vec3& p) {
    const Vec3i b(int(std::floor(p.x() / 8)) - g.block_lo().x(), int(std::floor(p.y() / 8)) - g.block_lo().y(),
                  int(std::floor(p.z() / 8)) - g.block_lo().z());
    for (int a = 0; a < 3; ++a)
        if (b[a] < 0 || b[a] >= g.block_count()[a]) return -1.0f;   // outside the majorant grid
    return g.majorant(b.x(), b.y(), b.z());
}

}  // namespace

TEST(DensityGrid, VoxelsMatchInput) {
    const DenseRef r = random_ref(1);
    const DensityGrid g = DensityGrid::from_dense(r.origin, r.dims, r.v);
    for (int z = r.origin.z() - 2; z < r.origin.z() + r.dims.z() + 2; ++z)
        for (int y = r.origin.y() - 2; y < r.origin.y() + r.dims.y() + 2; ++y)
            for (int x = r.origin.x() - 2; x < r.origin.x() + r.dims.x() + 2; ++x)
                ASSERT_EQ(g.voxel(x, y, z), r.at(x, y, z)) << x << " " << y << " " << z;
    EXPECT_FLOAT_EQ(g.max_density(), 50.0f);
}

TEST(DensityGrid, TrilinearMatchesBruteForce) {
    const DenseRef r = random_ref(2);
    const DensityGrid g = DensityGrid::from_dense(r.origin, r.dims, r.v);
    Rng rng(7);
    const Vec3 lo = r.origin.cast<double>() - Vec3::Constant(3.0);
    const Vec3 hi = (r.origin + r.dims).cast<double>() + Vec3::Constant(3.0);
    for (int i = 0; i < 200000; ++i) {
        const Vec3 p = random_point(rng, lo, hi);
        const double ref = r.trilinear(p);
        ASSERT_NEAR(g.density(p), ref, 1e-9 * (1.0 + std::abs(ref))) << p.transpose();
    }
    // Exactly at voxel centres the lookup returns the voxel.
    EXPECT_EQ(g.density(Vec3(0, 10, 0)), double(r.at(0, 10, 0)));
    // Outside and NaN give 0.
    EXPECT_EQ(g.density(Vec3(1e30, 0, 0)), 0.0);
    EXPECT_EQ(g.density(Vec3(std::nan(""), 10, 0)), 0.0);
    // Index bounds: 0 outside (lo - 1, hi + 1).
    const Bounds3& b = g.index_bounds();
    EXPECT_EQ(b.lo, r.origin.cast<double>() - Vec3::Ones());
    EXPECT_EQ(b.hi, (r.origin + r.dims).cast<double>());
}

TEST(DensityGrid, MajorantBoundsEveryLookupInItsBlock) {
    const DenseRef r = random_ref(3);
    const DensityGrid g = DensityGrid::from_dense(r.origin, r.dims, r.v);
    Rng rng(11);
    const Vec3 lo = r.origin.cast<double>() - Vec3::Constant(9.0);
    const Vec3 hi = (r.origin + r.dims).cast<double>() + Vec3::Constant(9.0);
    int tight = 0;
    for (int i = 0; i < 300000; ++i) {
        Vec3 p = random_point(rng, lo, hi);
        if (i % 3 == 0) p = (p.array().round() + 1e-12 * (rng.uniform() - 0.5)).matrix();   // near voxel/block faces
        const double d = g.density(p);
        const float m = majorant_at(g, p);
        if (m < 0) {
            ASSERT_EQ(d, 0.0) << "non-zero density outside the majorant grid at " << p.transpose();
            continue;
        }
        ASSERT_LE(d, double(m) * (1 + 1e-6)) << p.transpose();
        if (d > 0.5 * m) ++tight;
    }
    EXPECT_GT(tight, 1000);   // the majorants are not uselessly loose
}

TEST(DensityGrid, MajorantIsLocalForSingleDenseVoxel) {
    const Vec3i dims(64, 64, 64);
    std::vector<float> v(size_t(dims.prod()), 1e-3f);
    const Vec3i spike(40, 23, 31);   // 23 = 8*2 + 7: on a block's upper face, so two blocks in y see it
    v[(size_t(spike.z()) * dims.y() + spike.y()) * dims.x() + spike.x()] = 1e6f;
    const DensityGrid g = DensityGrid::from_dense(Vec3i::Zero(), dims, v);
    int hot = 0;
    for (int bx = 0; bx < g.block_count().x(); ++bx)
        for (int by = 0; by < g.block_count().y(); ++by)
            for (int bz = 0; bz < g.block_count().z(); ++bz)
                if (g.majorant(bx, by, bz) > 1.0f) ++hot;
    // Blocks whose voxels-plus-ring contain (40,23,31): x: blocks 5 and 4 (40 = 8*5 is in block
    // 4's upper ring), y: 2 and 3 (23 = 8*2+7), z: 3 and 4 (31 = 8*3+7). So 2*2*2 = 8.
    EXPECT_EQ(hot, 8);
    Rng rng(5);
    for (int i = 0; i < 100000; ++i) {
        const Vec3 p = spike.cast<double>() + Vec3(rng.uniform() * 2 - 1, rng.uniform() * 2 - 1, rng.uniform() * 2 - 1);
        ASSERT_LE(g.density(p), double(majorant_at(g, p)) * (1 + 1e-6)) << p.transpose();
    }
}

TEST(DensityGrid, TraverseVisitsContiguousBlocks) {
    const Vec3i dims(40, 33, 25);
    std::vector<float> v(size_t(dims.prod()), 1.0f);
    const DensityGrid g = DensityGrid::from_dense(Vec3i(-4, 0, 3), dims, v);
    Rng rng(9);
    for (int i = 0; i < 2000; ++i) {
        Vec3 o(rng.uniform() * 60 - 10, rng.uniform() * 50 - 10, rng.uniform() * 40 - 5);
        Vec3 d(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5);
        if (i % 4 == 0) d[i % 3] = 0.0;                          // axis-parallel components
        if (i % 8 == 0) o = o.array().round().matrix();           // on block/voxel faces
        double prev = -1;
        bool first = true;
        const double t1 = (i % 2) ? kInfinity : 30.0;
        g.traverse(o, d, 0.0, t1, [&](double ta, double tb, float) {
            EXPECT_LE(ta, tb);
            if (!first) {
                EXPECT_EQ(ta, prev);
            }
            EXPECT_TRUE(std::isfinite(tb));
            prev = tb;
            first = false;
            return true;
        });
    }
}

TEST(DensityGrid, HugeBoundingBoxIsRefused) {
    EXPECT_THROW(DensityGrid(Vec3i(-1000000000, 0, 0), Vec3i(1000000000, 1000000000, 1000000000)), std::length_error);
    EXPECT_THROW(DensityGrid(Vec3i(0, 0, 0), Vec3i(8 * 1024, 8 * 1024, 8 * 1024)), std::length_error);
    const DensityGrid ok(Vec3i(0, 0, 0), Vec3i(63, 63, 63));
    EXPECT_EQ(ok.block_total(), 9u * 9u * 9u);   // 8 blocks + 1 padding block per axis
}

TEST(DensityGrid, BlockWindowStencilsAreTheCellsVoxels) {
    // Every cell of every block (and of the blocks just outside the grid's range, whose windows
    // are all background), faces, edges and corners included: the window's stencil is the eight
    // voxels the reference holds, as stencil() reads them.
    const DenseRef ref = random_ref(11);
    const DensityGrid g = DensityGrid::from_dense(ref.origin, ref.dims, ref.v);
    int checked = 0, across = 0;
    for (int bx = g.block_lo().x() - 1; bx <= g.block_lo().x() + g.block_count().x(); ++bx)
        for (int by = g.block_lo().y() - 1; by <= g.block_lo().y() + g.block_count().y(); ++by)
            for (int bz = g.block_lo().z() - 1; bz <= g.block_lo().z() + g.block_count().z(); ++bz) {
                DensityGrid::BlockWindow w;
                g.block_window(bx * 8, by * 8, bz * 8, w);
                for (int c = 0; c < 512; ++c) {
                    const int cx = c >> 6, cy = (c >> 3) & 7, cz = c & 7;
                    const int x = bx * 8 + cx, y = by * 8 + cy, z = bz * 8 + cz;
                    double v[8], s[8];
                    DensityGrid::stencil(w, cx, cy, cz, v);
                    g.stencil(x, y, z, s);
                    for (int i = 0; i < 8; ++i) {
                        const double expected = ref.at(x + (i >> 2), y + ((i >> 1) & 1), z + (i & 1));
                        ASSERT_EQ(v[i], expected) << "cell " << x << " " << y << " " << z << " corner " << i;
                        ASSERT_EQ(s[i], expected);
                    }
                    ++checked;
                    across += cx == 7 || cy == 7 || cz == 7;
                }
            }
    EXPECT_GT(across, checked / 4);   // the cells whose stencils reach into the next blocks
}
