#include "scene/lights/emission_bounds.h"

#include <algorithm>
#include <cmath>

namespace vpm {

void EmissionBounds::set(const Bounds3& box) {
    box_ = box;
    levels_.clear();
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

void EmissionBounds::set_focus(const Bounds3& focus) {
    levels_.clear();
    if (empty() || focus.empty()) return;
    Bounds3 level;
    level.lo = focus.lo.cwiseMax(box_.lo);
    level.hi = focus.hi.cwiseMin(box_.hi);
    const Vec3 centre = 0.5 * (level.lo + level.hi);
    Vec3 half = 0.5 * (level.hi - level.lo);
    while (!level.empty()) {
        EmissionBounds b;
        b.set(level);
        if (!(b.area_ > 0.0) || b.area_ >= kFocusMaxAreaRatio * area_) break;
        levels_.push_back(std::move(b));
        half *= kFocusGrowth;
        level.lo = (centre - half).cwiseMax(box_.lo);
        level.hi = (centre + half).cwiseMin(box_.hi);
    }
}

std::vector<Bounds3> EmissionBounds::focus_levels() const {
    std::vector<Bounds3> out;
    for (const EmissionBounds& b : levels_) out.push_back(b.box_);
    return out;
}

EmissionLine EmissionBounds::sample_line(const Vec3& d, double u_pick, double u1, double u2) const {
    const double full_area = projected_area(d);
    if (levels_.empty()) return {sample_origin(d, u_pick, u1, u2), full_area};
    const size_t n = levels_.size() + 1;   // the focus levels and the box itself
    const double share = 1.0 / double(n);
    const size_t pick = std::min(size_t(u_pick * double(n)), n - 1);
    const double u_face = u_pick * double(n) - double(pick);
    EmissionLine line;
    if (pick + 1 == n || !(levels_[pick].projected_area(d) > 0.0)) {
        // The box itself (also for a flat level seen edge-on, which no line along d can be aimed at:
        // then that level's share goes to the box, and its term below is 0 for this d as well).
        line.origin = sample_origin(d, u_face, u1, u2);
    } else {
        // Over level `pick`'s silhouette, then back along -d to just outside the box.
        const Vec3 q = levels_[pick].sample_origin(d, u_face, u1, u2);
        double t0, t1;
        const double back = box_.intersect(Ray{q, -d}, kInfinity, t0, t1) ? t1 : 0.0;
        line.origin = q - (back + margin_) * d;
    }
    const Ray ray{line.origin, d};
    double density = share / full_area;
    double edge_on_share = 0.0;
    for (const EmissionBounds& level : levels_) {
        const double a = level.projected_area(d);
        double t0, t1;
        if (!(a > 0.0)) edge_on_share += share;
        else if (level.box_.intersect(ray, kInfinity, t0, t1)) density += share / a;
    }
    density += edge_on_share / full_area;
    line.area = 1.0 / density;
    return line;
}

}  // namespace vpm
