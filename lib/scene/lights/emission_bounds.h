#pragma once
// Where lights at infinity (directional, environment) emit photons: over the silhouette of the box
// around what can be lit (the scene's media and shapes, Scene::bounds), seen along the photon's
// direction, rather than over a disc covering the box's bounding sphere.
//
// Seen along a unit direction d, the faces of a box whose outward normal faces against d tile the
// silhouette without overlap; face i (normal along axis i, area A_i) projects to |d_i| A_i, so
//
//     A_proj(d) = |d_x| A_x + |d_y| A_y + |d_z| A_z,  and its mean over uniform d is S / 4 (Cauchy),
//
// S the box's surface area. A photon starts on a front face picked with probability |d_i| A_i /
// A_proj(d), uniformly on it, stepped back outside the box: uniform over the silhouette, and every
// such photon enters the box. Rays along d that miss the box can reach nothing, so their power is
// not emitted at all: a directional light's power is E A_proj(d), an environment's L pi S.
// For a box the disc wasted 1 - A_proj / (pi R^2) of the photons (e.g. 59% for a cube seen along an
// axis, 86% for a flat floor seen edge-on); here none miss the box.
#include "core/math.h"

namespace vpm {

class EmissionBounds {
public:
    void set(const Bounds3& box);
    bool empty() const { return area_ <= 0.0; }
    const Bounds3& box() const { return box_; }
    // Area of the box's silhouette seen along unit d.
    double projected_area(const Vec3& d) const;
    // Areas of the faces perpendicular to x, y and z (projected_area weighs them by |d_i|).
    const Vec3& face_area() const { return face_area_; }
    // Mean of projected_area over uniform directions: surface area / 4.
    double mean_projected_area() const { return 0.25 * area_; }
    // Origin of a ray along d, uniform over the silhouette, just outside the box.
    Vec3 sample_origin(const Vec3& d, double u_face, double u1, double u2) const;

private:
    Bounds3 box_;
    Vec3 face_area_ = Vec3::Zero();   // area of the faces perpendicular to x, y, z
    double area_ = 0.0;               // surface area
    double margin_ = 0.0;             // step back outside the box
};

}  // namespace vpm
