#pragma once
// Where a density grid's density is, as opposed to its index box (`vpm info` on a VDB, and the
// camera it suggests). A grid written by another tool often keeps active voxels of density 0 or a
// faint haze far from the smoke; framing its box frames mostly empty space.
//   nonzero: the world box of the voxels with density > 0 (each voxel's cell, centre +- half a voxel)
//   mass:    the world box that holds nearly all of the density: per axis, the voxel slabs between
//            the `trim` and 1 - `trim` quantiles of the density summed over the other two axes;
//            mass_inside says what share of the total it holds (at least 1 - 6 trim)
#include <cstdint>

#include "core/density_grid.h"
#include "core/math.h"

namespace vpm {

struct DensityExtent {
    Bounds3 nonzero;           // empty when the grid is 0 everywhere
    Bounds3 mass;
    double mass_inside = 0;    // share of the total density inside `mass`
    double total = 0;          // sum of the voxel densities
    int64_t nonzero_voxels = 0;
};

DensityExtent density_extent(const DensityGrid& grid, double trim = 0.001);

}  // namespace vpm
