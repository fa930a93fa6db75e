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
//
// Focus: in a scene much larger than the region the camera sees (scene/camera_region.h),
// nearly every such photon lands where no estimate gathers. Given a focus box F inside B whose
// surface area is below kFocusMaxAreaRatio of B's, lines are drawn from nested boxes instead:
// F_0 = F, F_1 = F grown kFocusGrowth times about its centre, F_2, ... (each clipped to B, while
// below that area ratio), and B itself, each with an equal share s = 1 / (levels + 1). A line of
// level j is uniform over F_j's silhouette, its origin moved back outside B. The one-sample
// mixture's density per unit area perpendicular to d is
//
//     s / A_B(d) + sum_j s [line meets F_j] / A_Fj(d),
//
// so a photon carries L / (p(d) x that density): its mean power is unchanged, the map unbiased.
// The nested levels make the photon density fall off gradually away from what the camera sees
// instead of dropping to B's: light that reaches the seen region sideways (a thin, wide slab, lit
// from the sky far away) is sampled at every distance, not only by rare heavy photons.
// A focus covering most of B changes nothing (the same rays, the same random numbers).
#include <vector>

#include "core/math.h"

namespace vpm {

constexpr double kFocusMaxAreaRatio = 0.25;
// Measured on the semi-infinite albedo-0.99 medium (8 maps of 2e5 photons): growth 4 gave the image
// mean a standard error of 0.0016, growth 2 0.0010, no focus 0.0020; smaller jumps in photon power
// between levels make lighter tails.
constexpr double kFocusGrowth = 2.0;

// A photon's line: where it starts and 1 / (its density per unit area perpendicular to d), which
// is A_B(d) without a focus.
struct EmissionLine {
    Vec3 origin = Vec3::Zero();
    double area = 0.0;
};

class EmissionBounds {
public:
    // Clears the focus.
    void set(const Bounds3& box);
    // Aims part of the lines at `focus` (clipped to the box); ignored when empty or not much
    // smaller than the box (see the top of the file).
    void set_focus(const Bounds3& focus);
    bool focused() const { return !levels_.empty(); }
    // The nested focus boxes F_0, F_1, ... (empty without a focus); B is the last level.
    std::vector<Bounds3> focus_levels() const;
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
    // A line along d from the mixture above (u_pick picks the level and is reused for the face).
    EmissionLine sample_line(const Vec3& d, double u_pick, double u1, double u2) const;

private:
    Bounds3 box_;
    Vec3 face_area_ = Vec3::Zero();   // area of the faces perpendicular to x, y, z
    double area_ = 0.0;               // surface area
    double margin_ = 0.0;             // step back outside the box
    std::vector<EmissionBounds> levels_;   // F_0, F_1, ...; empty: no focus
};

}  // namespace vpm
