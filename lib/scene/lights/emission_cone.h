#pragma once
// Where point and spot lights emit photons: toward what can be lit. Seen from a light outside the
// sphere around the scene's box (media and shapes), that sphere subtends a cone of half-angle
// asin(R / d); a direction outside the cone reaches nothing, so photons are emitted uniformly inside
// it with power I * solid_angle (the power that can arrive somewhere) instead of over the whole
// sphere with power 4 pi I. Uniform directions in the cone and I * solid_angle per photon give the
// same expected power in every direction of the cone as before: unbiased, with no photon wasted on
// empty space. A light inside the sphere keeps the whole sphere.
#include "core/math.h"
#include "core/sampling/sampling.h"

namespace vpm {

struct EmissionCone {
    bool full_sphere = true;
    Frame frame{Vec3::UnitZ()};   // frame.n: the cone's axis
    double cos_max = -1.0;
    double one_minus_cos = 2.0;   // 1 - cos_max, computed without cancellation

    // The cone from `position` around the sphere enclosing `box` (full sphere when inside or empty).
    static EmissionCone towards(const Vec3& position, const Bounds3& box) {
        EmissionCone c;
        if (box.empty()) return c;
        const Vec3 centre = 0.5 * (box.lo + box.hi);
        // Margins relative to the box and its distance from the origin, never absolute (
        // an absolute 1e-9 widened the cone of a scene scaled by 1e-6 by 3e-4).
        const double radius = 0.5 * (box.hi - box.lo).norm() * 1.001 + 1e-9 * centre.cwiseAbs().maxCoeff();
        const Vec3 to_centre = centre - position;
        const double d = to_centre.norm();
        if (!(d > radius) || !std::isfinite(d)) return c;
        const double s = radius / d;   // sin of the half-angle
        c.full_sphere = false;
        c.frame = Frame(to_centre / d);
        c.one_minus_cos = s * s / (1.0 + std::sqrt(1.0 - s * s));
        c.cos_max = 1.0 - c.one_minus_cos;
        return c;
    }
    double solid_angle() const { return full_sphere ? 4.0 * kPi : 2.0 * kPi * one_minus_cos; }
    Vec3 sample(double u1, double u2) const {
        if (full_sphere) return sample_uniform_sphere(u1, u2);
        // z = 1 - u1 (1 - cos_max), written with one_minus_cos so that tiny cones keep their width
        const double z = 1.0 - u1 * one_minus_cos;
        const double r = std::sqrt(std::max(0.0, u1 * one_minus_cos * (2.0 - u1 * one_minus_cos)));
        const double phi = 2.0 * kPi * u2;
        return frame.to_world(Vec3(r * std::cos(phi), r * std::sin(phi), z)).normalized();
    }
    // Whether unit direction w lies in the cone.
    bool contains(const Vec3& w) const { return full_sphere || w.dot(frame.n) >= cos_max; }
};

// Photons of a Lambertian area light that is far from its target (what it can light): a one-sample
// mixture of the cosine law and a direction uniform in the cone from the emitting point p towards
// the target, so that most photons go where they can land and the emitted power keeps its
// expectation L pi A. `choice` in [0, 1) picks the strategy, (u1, u2) sample it; the photon carries
// L A cos / p_mix (`weight`, per unit of radiance times area), 0 for a direction behind the surface.
struct AimedDirection {
    Vec3 dir;
    double weight = 0.0;
};

inline AimedDirection aim_cosine_or_cone(const Vec3& p, const Vec3& n, const Bounds3& target, double share,
                                         double choice, double u1, double u2) {
    const EmissionCone cone = EmissionCone::towards(p, target);
    AimedDirection a;
    a.dir = choice < share ? cone.sample(u1, u2) : Frame(n).to_world(sample_cosine_hemisphere(u1, u2)).normalized();
    const double cos = a.dir.dot(n);
    if (!(cos > 0.0)) return a;
    const double pdf = (1.0 - share) * cos / kPi + (cone.contains(a.dir) ? share / cone.solid_angle() : 0.0);
    a.weight = cos / pdf;
    return a;
}

// Whether a light of bounding radius `radius` around `centre` is far from `target`: further than
// twice their radii together (its emission cones are then much narrower than a hemisphere).
inline bool far_from_target(const Vec3& centre, double radius, const Bounds3& target) {
    if (target.empty()) return false;
    const Vec3 c = 0.5 * (target.lo + target.hi);
    return (c - centre).norm() > 2.0 * (0.5 * (target.hi - target.lo).norm() + radius);
}

}  // namespace vpm
