#include "scene/dielectric_regions.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "scene/media/ball_clip_moments.h"

namespace vpm {

namespace {

// A direction off every axis and diagonal, so parity rays do not run along a box's faces or edges.
const Vec3 kParityDir = Vec3(0.5773, 0.6129, 0.5397).normalized();

double radical_inverse(uint32_t i, uint32_t base) {
    double inv = 1.0 / base, f = inv, r = 0.0;
    for (; i > 0; i /= base, f *= inv) r += f * double(i % base);
    return r;
}

// kRegionBallPoints fixed points filling the unit ball uniformly (Halton 2, 3, 5 through the
// volume-preserving map: radius u^(1/3), direction uniform on the sphere), centre-symmetric pairs.
const std::vector<Vec3>& unit_ball_points() {
    static const std::vector<Vec3> points = [] {
        std::vector<Vec3> p;
        for (uint32_t i = 0; i < uint32_t(kRegionBallPoints / 2); ++i) {
            const double rad = std::cbrt((double(i) + 0.5) / double(kRegionBallPoints / 2));
            const double z = 1.0 - 2.0 * radical_inverse(i + 1, 3), phi = 2.0 * kPi * radical_inverse(i + 1, 5);
            const double s = std::sqrt(std::max(0.0, 1.0 - z * z));
            const Vec3 q = rad * Vec3(s * std::cos(phi), s * std::sin(phi), z);
            p.push_back(q);
            p.push_back(-q);
        }
        return p;
    }();
    return points;
}

// x's region carried along the segment from x to p: toggled at every glass surface crossed.
RegionMask region_along(const Surfaces& surfaces, const Vec3& x, RegionMask region, const Vec3& p) {
    Vec3 d = p - x;
    double left = d.norm();
    if (!(left > 0.0)) return region;
    d /= left;
    Ray ray{x, d};
    SurfaceHit hit;
    for (int crossings = 0; crossings < 64 && surfaces.intersect(ray, left, hit); ++crossings) {
        if (hit.dielectric >= 0) region ^= RegionMask(1) << hit.dielectric;
        left -= hit.t;
        ray.origin = hit.position;
    }
    return region;
}

// kRegionDiscPoints fixed points filling the unit disc uniformly (radius sqrt(u), the golden angle),
// in centre-symmetric pairs.
const std::vector<Vec3>& unit_disc_points() {
    static const std::vector<Vec3> points = [] {
        std::vector<Vec3> p;
        const double golden = kPi * (3.0 - std::sqrt(5.0));
        for (int i = 0; i < kRegionDiscPoints / 2; ++i) {
            const double rad = std::sqrt((double(i) + 0.5) / double(kRegionDiscPoints / 2)), phi = golden * double(i);
            const Vec3 q(rad * std::cos(phi), rad * std::sin(phi), 0.0);
            p.push_back(q);
            p.push_back(-q);
        }
        return p;
    }();
    return points;
}

// The area common to two discs in one plane: radii a and b, centres d apart.
double discs_overlap(double a, double b, double d) {
    if (d >= a + b) return 0.0;
    if (d <= std::abs(a - b)) return kPi * std::min(a, b) * std::min(a, b);
    const double ca = std::clamp((d * d + a * a - b * b) / (2.0 * d * a), -1.0, 1.0);
    const double cb = std::clamp((d * d + b * b - a * a) / (2.0 * d * b), -1.0, 1.0);
    const double kite = (-d + a + b) * (d + a - b) * (d - a + b) * (d + a + b);
    return a * a * std::acos(ca) + b * b * std::acos(cb) - 0.5 * std::sqrt(std::max(0.0, kite));
}

double distance_to_box(const Vec3& x, const Bounds3& b) {
    const Vec3 below = (b.lo - x).cwiseMax(0.0), above = (x - b.hi).cwiseMax(0.0);
    return (below + above).norm();
}

// How many glass shapes may cross the ball B(x, r) (spheres by their surface's distance, meshes by
// their bounds); `last` the index of the last.
int shapes_within(const std::vector<DielectricShape>& shapes, const Vec3& x, double r, int& last) {
    int count = 0;
    for (size_t i = 0; i < shapes.size(); ++i) {
        const DielectricShape& s = shapes[i];
        if (s.sphere ? std::abs((x - s.center).norm() - s.radius) < r : distance_to_box(x, s.bounds) < r) {
            last = int(i);
            ++count;
        }
    }
    return count;
}

}  // namespace

RegionMask region_at(const Surfaces* surfaces, const Vec3& x) {
    if (!surfaces) return 0;
    const auto& shapes = surfaces->dielectric_shapes();
    RegionMask region = 0;
    bool meshes = false;
    for (size_t i = 0; i < shapes.size(); ++i) {
        const DielectricShape& s = shapes[i];
        if (s.sphere) {
            if ((x - s.center).squaredNorm() < s.radius * s.radius) region |= RegionMask(1) << i;
        } else if (distance_to_box(x, s.bounds) == 0.0) {
            meshes = true;
        }
    }
    if (!meshes) return region;
    // Parity of the crossings of each mesh along a ray to infinity (spheres were read above).
    RegionMask parity = 0;
    Ray ray{x, kParityDir};
    SurfaceHit hit;
    for (int crossings = 0; crossings < 4096 && surfaces->intersect(ray, kInfinity, hit); ++crossings) {
        if (hit.dielectric >= 0 && !shapes[size_t(hit.dielectric)].sphere) parity ^= RegionMask(1) << hit.dielectric;
        ray.origin = hit.position;
    }
    return region | parity;
}

double region_ball_fraction(const Surfaces* surfaces, const Vec3& x, double r, RegionMask region) {
    if (!surfaces || !(r > 0.0)) return 1.0;
    const auto& shapes = surfaces->dielectric_shapes();
    int crossing = -1;
    const int crossings = shapes_within(shapes, x, r, crossing);
    if (crossings == 0) return 1.0;
    if (crossings == 1 && shapes[size_t(crossing)].sphere) {
        const DielectricShape& s = shapes[size_t(crossing)];
        const double ball = 4.0 / 3.0 * kPi * r * r * r;
        const double inside = ball_ball_moments(r, s.center - x, s.radius).m0 / ball;
        const double f = (region >> crossing) & 1 ? inside : 1.0 - inside;
        return f > 0.0 ? f : 1.0;   // x on the surface itself, at round-off: no share to correct by
    }
    int in = 0;
    for (const Vec3& u : unit_ball_points())
        if (region_along(*surfaces, x, region, x + r * u) == region) ++in;
    return in > 0 ? double(in) / double(kRegionBallPoints) : 1.0;
}

double region_disc_fraction(const Surfaces* surfaces, const Vec3& x, const Vec3& n, double r, RegionMask region) {
    if (!surfaces || !(r > 0.0)) return 1.0;
    const auto& shapes = surfaces->dielectric_shapes();
    int crossing = -1;
    const int crossings = shapes_within(shapes, x, r, crossing);
    if (crossings == 0) return 1.0;
    if (crossings == 1 && shapes[size_t(crossing)].sphere) {
        // The sphere cuts the disc's plane in a circle of radius rho about c's foot in the plane.
        const DielectricShape& s = shapes[size_t(crossing)];
        const Vec3 to_center = s.center - x;
        const double h = to_center.dot(n), rho2 = s.radius * s.radius - h * h;
        const double inside = rho2 > 0.0 ? discs_overlap(r, std::sqrt(rho2), (to_center - h * n).norm()) / (kPi * r * r) : 0.0;
        const double f = (region >> crossing) & 1 ? inside : 1.0 - inside;
        return f > 0.0 ? f : 1.0;   // x on the sphere itself, at round-off: no share to correct by
    }
    const Frame frame(n);
    int in = 0;
    for (const Vec3& u : unit_disc_points())
        if (region_along(*surfaces, x, region, x + r * frame.to_world(u)) == region) ++in;
    return in > 0 ? double(in) / double(kRegionDiscPoints) : 1.0;
}

ClipMoments shape_ball_moments(const Surfaces& surfaces, const Vec3& x, double r, int shape) {
    const RegionMask region = region_at(&surfaces, x), bit = RegionMask(1) << shape;
    const double w = (4.0 / 3.0) * kPi * r * r * r / kRegionBallPoints;
    ClipMoments m;
    for (const Vec3& u : unit_ball_points()) {
        if (!(region_along(surfaces, x, region, x + r * u) & bit)) continue;
        const Vec3 d = r * u;
        m.m0 += w;
        m.m1 += w * d;
        m.m2 += w * (d * d.transpose());
    }
    return m;
}

}  // namespace vpm
