#pragma once
// The disc through which lights at infinity (directional, environment) emit photons.
#include "core/math.h"
#include "core/sampling.h"

namespace vpm {

// A disc perpendicular to `dir` that covers the scene's bounding sphere: lights at infinity
// emit photons through it, so every photon that can reach the scene is sampled exactly once.
struct SceneDisc {
    Vec3 center = Vec3::Zero();
    double radius = 0.0;
    void set(const Bounds3& b) {
        if (b.empty()) { center = Vec3::Zero(); radius = 0.0; return; }
        center = 0.5 * (b.lo + b.hi);
        radius = 0.5 * (b.hi - b.lo).norm() * 1.001 + 1e-9;
    }
    // Origin of a ray travelling along `dir` that starts outside the bounding sphere.
    Vec3 sample_origin(const Vec3& dir, double u1, double u2) const {
        const Frame f(dir);
        const Eigen::Vector2d d = radius * sample_uniform_disc(u1, u2);
        return center - radius * dir + d.x() * f.s + d.y() * f.t;
    }
    double area() const { return kPi * radius * radius; }
};

}  // namespace vpm
