#include "scene/lights/emission_bounds.h"

#include <algorithm>
#include <cmath>

namespace vpm {

void EmissionBounds::set(const Bounds3& box) {
    box_ = box;
    face_area_ = Vec3::Zero();
    area_ = 0.0;
    margin_ = 0.0;
    if (box.empty()) return;
    const Vec3 e = box.hi - box.lo;
    face_area_ = Vec3(e[1] * e[2], e[0] * e[2], e[0] * e[1]);
    area_ = 2.0 * face_area_.sum();
    // An area that overflows (bounds beyond ~1e154) is kept: the light's power() is then not
    // finite, which Scene::build refuses, instead of the light silently emitting nothing.
    margin_ = 1e-4 * e.norm() + 1e-9 * std::max(box.lo.cwiseAbs().maxCoeff(), box.hi.cwiseAbs().maxCoeff()) + 1e-12;
}

double EmissionBounds::projected_area(const Vec3& d) const {
    return std::abs(d[0]) * face_area_[0] + std::abs(d[1]) * face_area_[1] + std::abs(d[2]) * face_area_[2];
}

Vec3 EmissionBounds::sample_origin(const Vec3& d, double u_face, double u1, double u2) const {
    const Vec3 w(std::abs(d[0]) * face_area_[0], std::abs(d[1]) * face_area_[1], std::abs(d[2]) * face_area_[2]);
    const double total = w.sum();
    int axis = 2;
    if (u_face * total < w[0]) axis = 0;
    else if (u_face * total < w[0] + w[1]) axis = 1;
    const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
    Vec3 p;
    p[axis] = d[axis] > 0.0 ? box_.lo[axis] : box_.hi[axis];   // the face the ray enters through
    p[a1] = box_.lo[a1] + u1 * (box_.hi[a1] - box_.lo[a1]);
    p[a2] = box_.lo[a2] + u2 * (box_.hi[a2] - box_.lo[a2]);
    return p - margin_ * d;
}

}  // namespace vpm
