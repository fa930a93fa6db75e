#pragma once
// Triangle-mesh loaders for OBJ and PLY (compact readers of our own; no Debian package fits:
// tinyobjloader reports no line numbers in the form we need, and there is no PLY library).
//
// OBJ: `v x y z [w]` and `f` with polygons triangulated as fans; vertex references may be
// `i`, `i/t`, `i//n`, `i/t/n`, positive (1-based) or negative (relative to the vertices read
// so far). A face may only reference vertices defined above it. vt/vn/vp/usemtl/mtllib/o/g/s/l/p
// lines are ignored; any other statement is an error (free-form geometry is not supported).
// Errors: FileError "<file>:<line>: <what>".
//
// PLY: ascii, binary_little_endian and binary_big_endian, version 1.0. Element "vertex" needs
// scalar properties x, y, z (any numeric type; float/double in practice); element "face" needs a
// list property "vertex_indices" (or "vertex_index") with an integer count and integer indices.
// Every other element and property is skipped correctly. Errors: FileError "<file>: <what>".
//
// Both loaders reject non-finite coordinates, out-of-range indices, faces with fewer than three
// vertices and meshes without faces.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/math.h"

namespace vpm {

struct TriangleMesh {
    std::vector<Vec3> vertices;
    std::vector<std::array<uint32_t, 3>> triangles;
};

TriangleMesh load_obj(const std::string& path);
TriangleMesh load_ply(const std::string& path);
// Chooses by extension (.obj / .ply, case-insensitive); FileError for any other.
TriangleMesh load_mesh(const std::string& path);

}  // namespace vpm
