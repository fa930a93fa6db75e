#pragma once
// Glass resting flat on another surface (a bottle's base on a floor, in one plane) is not
// reciprocal in a ray tracer: light refracted out of the glass face starts past the surface under it
// and misses it, while paths leaving that surface pass into the glass. Photons (from the lights) and
// camera paths then see different scenes, and the photon map disagrees with the path tracer
// (docs/interior_medium.md). The scene warns; a small gap between the two removes it.
#include <array>
#include <cstdint>
#include <vector>

#include "core/math.h"

namespace vpm {

struct TriangleMeshView {
    const std::vector<Vec3>& vertices;
    const std::vector<std::array<uint32_t, 3>>& triangles;
};

// Pairs of triangles tested at most: a pair of larger meshes is not checked (false).
constexpr double kCoplanarPairLimit = 2e7;

// Whether a triangle of `a` and one of `b` lie in one plane (parallel within 1e-9, within rounding
// at their size of each other's plane) and overlap (a centroid or a vertex of one inside the other).
bool touch_in_a_plane(const TriangleMeshView& a, const TriangleMeshView& b);

}  // namespace vpm
