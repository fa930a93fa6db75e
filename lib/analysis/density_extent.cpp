#include "analysis/density_extent.h"

#include <vector>

namespace vpm {

namespace {

// The world box of the voxel cells [lo - 0.5, hi + 0.5] in index space.
Bounds3 world_box(const DensityGrid& g, const Vec3i& lo, const Vec3i& hi) {
    Bounds3 b;
    for (int corner = 0; corner < 8; ++corner) {
        const Vec3 p((corner & 1) ? hi.x() + 0.5 : lo.x() - 0.5, (corner & 2) ? hi.y() + 0.5 : lo.y() - 0.5,
                     (corner & 4) ? hi.z() + 0.5 : lo.z() - 0.5);
        b.extend(g.index_to_world() * p);
    }
    return b;
}

}  // namespace

DensityExtent density_extent(const DensityGrid& g, double trim) {
    DensityExtent e;
    if (g.empty()) return e;
    const Vec3i lo = g.voxel_lo(), hi = g.voxel_hi();
    const Vec3i n = hi - lo + Vec3i::Ones();
    // Per axis, the density summed over the other two (the marginals), and the non-zero box.
    std::vector<double> marginal[3] = {std::vector<double>(size_t(n.x()), 0.0), std::vector<double>(size_t(n.y()), 0.0),
                                       std::vector<double>(size_t(n.z()), 0.0)};
    Vec3i nz_lo = hi, nz_hi = lo;
    for (int z = lo.z(); z <= hi.z(); ++z)
        for (int y = lo.y(); y <= hi.y(); ++y)
            for (int x = lo.x(); x <= hi.x(); ++x) {
                const double d = g.voxel(x, y, z);
                if (!(d > 0)) continue;
                ++e.nonzero_voxels;
                e.total += d;
                marginal[0][size_t(x - lo.x())] += d;
                marginal[1][size_t(y - lo.y())] += d;
                marginal[2][size_t(z - lo.z())] += d;
                nz_lo = nz_lo.cwiseMin(Vec3i(x, y, z));
                nz_hi = nz_hi.cwiseMax(Vec3i(x, y, z));
            }
    if (e.nonzero_voxels == 0) return e;
    e.nonzero = world_box(g, nz_lo, nz_hi);
    Vec3i m_lo, m_hi;
    for (int a = 0; a < 3; ++a) {
        const std::vector<double>& m = marginal[a];
        double below = 0;
        size_t first = 0;
        while (first + 1 < m.size() && below + m[first] <= trim * e.total) below += m[first++];
        double above = 0;
        size_t last = m.size() - 1;
        while (last > first && above + m[last] <= trim * e.total) above += m[last--];
        m_lo[a] = lo[a] + int(first);
        m_hi[a] = lo[a] + int(last);
    }
    e.mass = world_box(g, m_lo, m_hi);
    double inside = 0;
    for (int z = m_lo.z(); z <= m_hi.z(); ++z)
        for (int y = m_lo.y(); y <= m_hi.y(); ++y)
            for (int x = m_lo.x(); x <= m_hi.x(); ++x) {
                const double d = g.voxel(x, y, z);
                if (d > 0) inside += d;
            }
    e.mass_inside = inside / e.total;
    return e;
}

}  // namespace vpm
