#pragma once
// Smooth dielectric interfaces: the exact Fresnel reflectance of unpolarised light (the mean of
// the s and p reflectances) and Snell's law. `eta` is the index of the side the light enters over
// that of the side it comes from (1.5 for air into glass, 1 / 1.5 back out).
#include "core/math.h"

namespace vpm {

// cos_i = cos of the angle to the normal on the incident side, in [0, 1]. Returns F in [0, 1]; 1 for
// total internal reflection. `cos_t` receives the cosine of the refracted angle (0 under TIR).
double fresnel_dielectric(double cos_i, double eta, double& cos_t);
inline double fresnel_dielectric(double cos_i, double eta) {
    double cos_t;
    return fresnel_dielectric(cos_i, eta, cos_t);
}

// Mirror direction of travel d about the unit normal n (either orientation).
inline Vec3 reflect(const Vec3& d, const Vec3& n) { return d - 2.0 * d.dot(n) * n; }

// Refracted direction of travel for d meeting the unit normal n (n . d < 0), given cos_t from
// fresnel_dielectric (not under TIR).
inline Vec3 refract(const Vec3& d, const Vec3& n, double eta, double cos_t) {
    const double cos_i = -d.dot(n);
    return (d / eta + (cos_i / eta - cos_t) * n).normalized();
}

}  // namespace vpm
