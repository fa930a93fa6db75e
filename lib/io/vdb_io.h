#pragma once
// Reading and writing density grids as OpenVDB files. vdb_io.cpp is the only file in vpm that
// includes OpenVDB headers (they are slow to compile and leak macros).
#include <string>
#include <vector>

#include "core/density_grid.h"

namespace vpm {

// Loads scalar grid `grid_name` (float, or double converted to float; empty name: the first such
// grid in the file) into a finalized DensityGrid, keeping the file's index-to-world transform (which must be affine).
// Throws FileError "<path>: ..." for a missing, unreadable, truncated or non-VDB file and for
// bad contents (non-finite or negative voxel values, non-zero background, empty grid,
// non-affine transform), and ConfigError "<path>: ..." when the requested grid is absent or
// not a float/double grid; those messages list the grids found with their types.
DensityGrid load_vdb_density(const std::string& path, const std::string& grid_name = "");

// Names and value types ("float", "vec3s", ...) of the grids in a file, in file order.
struct VdbGridInfo {
    std::string name;
    std::string type;
};
std::vector<VdbGridInfo> list_vdb_grids(const std::string& path);

// Writes `grid` as a float grid called `name` (voxels != 0 active, background 0, the grid's
// index-to-world as the transform; must be affine with a uniform-or-not linear part), with
// OpenVDB's default compression (blosc when available, else zip). Writes to a temporary name
// and renames, so no partial file is left behind. Throws FileError on failure.
void write_vdb_density(const std::string& path, const std::string& name, const DensityGrid& grid);

// Test helper: writes a small VDB with one grid of another value type ("vec3s", "int32"), an
// empty float grid ("empty_float") or a float grid with a frustum transform ("frustum_float"),
// to exercise the loader's errors.
void write_vdb_test_grid(const std::string& path, const std::string& name, const std::string& kind);

}  // namespace vpm
