#pragma once
// core/: the bottom layer, depending on nothing else of vpm: math (this file), rng (PCG32
// streams), sampling, piecewise-constant distributions, Henyey-Greenstein, progress and timers, errors, build info.
//
// Basic types shared by all of vpm. Positions and directions are double precision (scenes may
// sit far from the origin); colours are RGB arrays so that products are component-wise.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <limits>

namespace vpm {

using Vec3 = Eigen::Vector3d;
using Rgb = Eigen::Array3d;

constexpr double kPi = 3.14159265358979323846;
constexpr double kInvPi = 1.0 / kPi;
constexpr double kInv4Pi = 1.0 / (4.0 * kPi);
constexpr double kInfinity = std::numeric_limits<double>::infinity();

// A ray with a unit-length direction; distances along it are in world units.
struct Ray {
    Vec3 origin = Vec3::Zero();
    Vec3 dir = Vec3::UnitZ();
    Vec3 at(double t) const { return origin + t * dir; }
};

// Axis-aligned box; empty when lo > hi in any axis.
struct Bounds3 {
    Vec3 lo = Vec3::Constant(kInfinity);
    Vec3 hi = Vec3::Constant(-kInfinity);

    bool empty() const { return (lo.array() > hi.array()).any(); }
    void extend(const Vec3& p) { lo = lo.cwiseMin(p); hi = hi.cwiseMax(p); }
    void extend(const Bounds3& b) { lo = lo.cwiseMin(b.lo); hi = hi.cwiseMax(b.hi); }
    bool contains(const Vec3& p) const {
        return (p.array() >= lo.array()).all() && (p.array() <= hi.array()).all();
    }
    // Slab test: the parameter interval [t0, t1] of the ray inside the box, clipped to [0, tmax].
    // An empty box (lo > hi: its slabs swap into the whole line) is missed by every ray.
    bool intersect(const Ray& ray, double tmax, double& t0, double& t1) const {
        t0 = 0.0;
        t1 = tmax;
        for (int a = 0; a < 3; ++a) {
            if (lo[a] > hi[a]) return false;
            const double inv = 1.0 / ray.dir[a];   // +-inf for axis-parallel rays is intended
            double tn = (lo[a] - ray.origin[a]) * inv;
            double tf = (hi[a] - ray.origin[a]) * inv;
            if (tn > tf) std::swap(tn, tf);
            if (std::isnan(tn) || std::isnan(tf)) {   // origin on a slab plane of a parallel ray
                if (ray.origin[a] < lo[a] || ray.origin[a] > hi[a]) return false;
                continue;
            }
            t0 = std::max(t0, tn);
            t1 = std::min(t1, tf);
            if (t0 > t1) return false;
        }
        return true;
    }
};

// Orthonormal frame around a unit vector n (Duff et al. 2017, branchless and stable).
struct Frame {
    Vec3 s, t, n;
    explicit Frame(const Vec3& normal) : n(normal) {
        const double sign = std::copysign(1.0, n.z());
        const double a = -1.0 / (sign + n.z());
        const double b = n.x() * n.y() * a;
        s = Vec3(1.0 + sign * n.x() * n.x() * a, sign * b, -sign * n.x());
        t = Vec3(b, sign + n.y() * n.y() * a, -n.y());
    }
    Vec3 to_world(const Vec3& v) const { return v.x() * s + v.y() * t + v.z() * n; }
    Vec3 to_local(const Vec3& v) const { return Vec3(v.dot(s), v.dot(t), v.dot(n)); }
};

inline double luminance(const Rgb& c) { return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]; }
inline bool all_finite(const Rgb& c) { return std::isfinite(c[0]) && std::isfinite(c[1]) && std::isfinite(c[2]); }

}  // namespace vpm
