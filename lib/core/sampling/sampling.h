#pragma once
// Warps from the unit square to directions and positions, each with its pdf.
#include "core/math.h"
#include "core/sampling/turn_sincos.h"

namespace vpm {

inline Vec3 sample_uniform_sphere(double u1, double u2) {
    const double z = 1.0 - 2.0 * u1;
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    const SinCos a = sincos_turns(u2);   // azimuth 2 pi u2
    return Vec3(r * a.cos, r * a.sin, z);
}
constexpr double uniform_sphere_pdf() { return kInv4Pi; }

// Uniform direction in the cone of half-angle acos(cos_max) around +z.
inline Vec3 sample_uniform_cone(double u1, double u2, double cos_max) {
    const double z = 1.0 - u1 * (1.0 - cos_max);
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    const SinCos a = sincos_turns(u2);   // azimuth 2 pi u2
    return Vec3(r * a.cos, r * a.sin, z);
}
inline double uniform_cone_pdf(double cos_max) { return 1.0 / (2.0 * kPi * (1.0 - cos_max)); }

// Cosine-weighted direction on the +z hemisphere (Malley's method); pdf = cos / pi.
inline Vec3 sample_cosine_hemisphere(double u1, double u2) {
    const double r = std::sqrt(u1);
    const SinCos a = sincos_turns(u2);
    return Vec3(r * a.cos, r * a.sin, std::sqrt(std::max(0.0, 1.0 - u1)));
}

// Uniform point in the unit disc (polar map; uniform in area).
inline Eigen::Vector2d sample_uniform_disc(double u1, double u2) {
    const double r = std::sqrt(u1);
    const SinCos a = sincos_turns(u2);
    return Eigen::Vector2d(r * a.cos, r * a.sin);
}

// Uniform point in the unit ball.
inline Vec3 sample_uniform_ball(double u1, double u2, double u3) {
    return std::cbrt(u3) * sample_uniform_sphere(u1, u2);
}

}  // namespace vpm
