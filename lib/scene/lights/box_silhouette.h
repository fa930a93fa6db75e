#pragma once
// Directions from a point outside an axis-aligned box, uniform over the solid angle the box covers
// (its silhouette). Seen from outside, the box shows at most three faces, one per axis on whose
// far side the point lies, and their spherical projections tile the silhouette without overlap; so
// a face is picked with probability proportional to its solid angle and a direction is drawn
// uniformly inside that face's spherical rectangle (the area-preserving map of Urena, Fajardo and
// King, "An area-preserving parametrization for spherical rectangles", 2013). A point light that
// emits this way wastes no photon on directions that meet nothing, however near the box it is.
#include <array>

#include "core/math.h"

namespace vpm {

class BoxSilhouette {
public:
    // Below this solid angle (sr) the parametrisation loses precision (its angles are O(1) and the
    // solid angle their small difference); callers use a bounding cone instead.
    static constexpr double kMinSolidAngle = 1e-6;

    // The silhouette of `box` seen from `from`; valid() is false where `from` lies in the box, the
    // box is empty or flat as seen from there, or its solid angle is under kMinSolidAngle.
    BoxSilhouette(const Vec3& from, const Bounds3& box);
    bool valid() const { return solid_angle_ >= kMinSolidAngle; }
    double solid_angle() const { return solid_angle_; }
    // A unit direction uniform over the silhouette from three uniform numbers in [0, 1).
    Vec3 sample(double u_face, double u1, double u2) const;

private:
    // One visible face as a spherical rectangle, in a frame (x, y, z) whose origin is the viewpoint:
    // the face spans [x0, x1] x [y0, y1] at height z0 < 0.
    struct Face {
        Vec3 x, y, z;
        double x0, x1, y0, y1, z0;
        double b0, b1, k, solid_angle;
    };
    static bool make_face(const Vec3& corner, const Vec3& edge_x, const Vec3& edge_y, Face& f);
    static Vec3 sample_face(const Face& f, double u1, double u2);

    std::array<Face, 3> faces_{};
    int face_count_ = 0;
    double solid_angle_ = 0.0;
};

}  // namespace vpm
