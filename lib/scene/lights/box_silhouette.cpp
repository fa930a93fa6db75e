#include "scene/lights/box_silhouette.h"

#include <algorithm>
#include <cmath>

namespace vpm {

BoxSilhouette::BoxSilhouette(const Vec3& from, const Bounds3& box) {
    if (box.empty() || box.contains(from)) return;
    const Vec3 extent = box.hi - box.lo;
    for (int a = 0; a < 3; ++a) {
        // The face of axis a that faces `from`, if `from` lies beyond it.
        double plane;
        if (from[a] < box.lo[a]) plane = box.lo[a];
        else if (from[a] > box.hi[a]) plane = box.hi[a];
        else continue;
        const int b = (a + 1) % 3, c = (a + 2) % 3;
        // Coordinates relative to the viewpoint, so that a far-from-origin scene keeps its digits.
        Vec3 corner = box.lo - from;
        corner[a] = plane - from[a];
        Vec3 edge_x = Vec3::Zero(), edge_y = Vec3::Zero();
        edge_x[b] = extent[b];
        edge_y[c] = extent[c];
        Face f;
        if (make_face(corner, edge_x, edge_y, f)) {
            faces_[face_count_++] = f;
            solid_angle_ += f.solid_angle;
        }
    }
    if (!(solid_angle_ >= kMinSolidAngle)) {
        face_count_ = 0;
        solid_angle_ = 0.0;
    }
}

bool BoxSilhouette::make_face(const Vec3& corner, const Vec3& edge_x, const Vec3& edge_y, Face& f) {
    const double lx = edge_x.norm(), ly = edge_y.norm();
    if (!(lx > 0.0) || !(ly > 0.0)) return false;
    f.x = edge_x / lx;
    f.y = edge_y / ly;
    f.z = f.x.cross(f.y);
    f.z0 = corner.dot(f.z);
    if (f.z0 > 0.0) {   // the rectangle below the viewpoint in its own frame
        f.z = -f.z;
        f.z0 = -f.z0;
    }
    if (!(f.z0 < 0.0)) return false;   // the viewpoint in the face's plane sees it edge-on
    f.x0 = corner.dot(f.x);
    f.y0 = corner.dot(f.y);
    f.x1 = f.x0 + lx;
    f.y1 = f.y0 + ly;
    // Unit normals of the four great circles through the viewpoint and the rectangle's edges, and
    // the spherical rectangle's interior angles between them; their sum less 2 pi is its area.
    const double z0 = f.z0;
    const Vec3 n0 = Vec3(0.0, z0, -f.y0).normalized();
    const Vec3 n1 = Vec3(-z0, 0.0, f.x1).normalized();
    const Vec3 n2 = Vec3(0.0, -z0, f.y1).normalized();
    const Vec3 n3 = Vec3(z0, 0.0, -f.x0).normalized();
    const auto angle = [](const Vec3& p, const Vec3& q) { return std::acos(std::clamp(-p.dot(q), -1.0, 1.0)); };
    const double g0 = angle(n0, n1), g1 = angle(n1, n2), g2 = angle(n2, n3), g3 = angle(n3, n0);
    f.b0 = n0.z();
    f.b1 = n2.z();
    f.k = 2.0 * kPi - g2 - g3;
    f.solid_angle = g0 + g1 - f.k;
    return f.solid_angle > 0.0;
}

Vec3 BoxSilhouette::sample_face(const Face& f, double u1, double u2) {
    // u1 sweeps the area from the x0 edge: invert the area of the part left of x = xu for xu.
    const double au = u1 * f.solid_angle + f.k;
    const double fu = (std::cos(au) * f.b0 - f.b1) / std::sin(au);
    const double cu = std::clamp(std::copysign(1.0, fu) / std::sqrt(fu * fu + f.b0 * f.b0), -1.0, 1.0);
    const double sin_u = std::sqrt(std::max(0.0, 1.0 - cu * cu));
    // Rounding can put xu a hair outside the face; the clamp keeps the direction on it.
    const double xu = sin_u > 0.0 ? std::clamp(-cu * f.z0 / sin_u, f.x0, f.x1) : (cu > 0.0 ? f.x1 : f.x0);
    // u2 is uniform in the height's sine along the great circle through xu.
    const double d = std::sqrt(xu * xu + f.z0 * f.z0);
    const double h0 = f.y0 / std::sqrt(d * d + f.y0 * f.y0);
    const double h1 = f.y1 / std::sqrt(d * d + f.y1 * f.y1);
    const double hv = h0 + u2 * (h1 - h0);
    const double hv2 = hv * hv;
    const double yv = hv2 < 1.0 ? std::clamp(hv * d / std::sqrt(1.0 - hv2), f.y0, f.y1) : f.y1;
    return (xu * f.x + yv * f.y + f.z0 * f.z).normalized();
}

Vec3 BoxSilhouette::sample(double u_face, double u1, double u2) const {
    // The face by its share of the solid angle; the direction inside it takes its own two numbers.
    double pick = u_face * solid_angle_;
    int i = 0;
    while (i + 1 < face_count_ && pick >= faces_[i].solid_angle) pick -= faces_[i++].solid_angle;
    return sample_face(faces_[i], u1, u2);
}

}  // namespace vpm
