#include "scene/surfaces/coplanar_contact.h"

#include <algorithm>
#include <cfloat>
#include <cmath>

#include "scene/surfaces/offsets.h"

namespace vpm {

namespace {

struct Triangle {
    Vec3 a, b, c, n;   // n: unit normal (zero when degenerate)
    Bounds3 bounds;
};

std::vector<Triangle> triangles_of(const TriangleMeshView& m) {
    std::vector<Triangle> out;
    out.reserve(m.triangles.size());
    for (const auto& t : m.triangles) {
        Triangle tri{m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]], Vec3::Zero(), Bounds3{}};
        const Vec3 n = (tri.b - tri.a).cross(tri.c - tri.a);
        if (n.norm() > 0.0) tri.n = n.normalized();
        for (const Vec3* v : {&tri.a, &tri.b, &tri.c}) tri.bounds.extend(*v);
        out.push_back(tri);
    }
    return out;
}

// p strictly inside t, p taken in t's plane.
bool inside(const Triangle& t, const Vec3& p) {
    const Vec3* v[3] = {&t.a, &t.b, &t.c};
    for (int i = 0; i < 3; ++i)
        if ((*v[(i + 1) % 3] - *v[i]).cross(p - *v[i]).dot(t.n) <= 0.0) return false;
    return true;
}

// A few points of t's interior: its centroid and its vertices pulled a little towards it.
std::array<Vec3, 4> interior_points(const Triangle& t) {
    const Vec3 c = (t.a + t.b + t.c) / 3.0;
    return {c, t.a + 0.01 * (c - t.a), t.b + 0.01 * (c - t.b), t.c + 0.01 * (c - t.c)};
}

bool boxes_touch(const Bounds3& p, const Bounds3& q, double tol) {
    return (p.lo.array() <= q.hi.array() + tol).all() && (q.lo.array() <= p.hi.array() + tol).all();
}

// How far apart two triangles' planes count as one: a spawned ray's offset at their coordinates
// (offsets.h), or float rounding at their own size (Embree sees coordinates about the scene's
// centre, so a triangle far from the origin is resolved at its size, not at its distance).
double plane_tolerance(const Triangle& s, const Triangle& t) {
    const double size = (s.bounds.hi - s.bounds.lo).maxCoeff() + (t.bounds.hi - t.bounds.lo).maxCoeff();
    return std::max(kSpawnOffset * (magnitude(s.a) + magnitude(t.a)), 8.0 * FLT_EPSILON * size);
}

// tol: plane_tolerance.
bool pair_touches(const Triangle& s, const Triangle& t, double tol) {
    if (s.n.isZero() || t.n.isZero() || std::abs(s.n.dot(t.n)) < 1.0 - 1e-9) return false;
    if (std::abs(t.n.dot(s.a - t.a)) > tol) return false;
    for (const Vec3& p : interior_points(s))
        if (inside(t, p)) return true;
    for (const Vec3& p : interior_points(t))
        if (inside(s, p)) return true;
    return false;
}

}  // namespace

bool touch_in_a_plane(const TriangleMeshView& a, const TriangleMeshView& b) {
    if (double(a.triangles.size()) * double(b.triangles.size()) > kCoplanarPairLimit) return false;
    const std::vector<Triangle> ta = triangles_of(a), tb = triangles_of(b);
    for (const Triangle& s : ta)
        for (const Triangle& t : tb) {
            const double tol = plane_tolerance(s, t);
            if (boxes_touch(s.bounds, t.bounds, tol) && pair_touches(s, t, tol)) return true;
        }
    return false;
}

}  // namespace vpm
