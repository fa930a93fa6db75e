#pragma once
// A homogeneous medium filling a box or a sphere. Free flights and transmittance in closed form.
//
//   type = "homogeneous"
//   shape = "box" (min, max) | "sphere" (center, radius > 0)
//   sigma_t_scale >= 0   extinction (1/length); the density inside the shape is 1
//   albedo in [0, 1] (rgb)   g in (-1, 1)
#include <memory>

#include "scene/media/medium.h"
#include "config/params.h"

namespace vpm {

class HomogeneousMedium : public Medium {
public:
    enum class Shape { box, sphere };
    // Box: a = min, b = max. Sphere: a = center, radius.
    static HomogeneousMedium box(const Vec3& lo, const Vec3& hi, double sigma_t, const Rgb& albedo, double g);
    static HomogeneousMedium sphere(const Vec3& center, double radius, double sigma_t, const Rgb& albedo, double g);

    Bounds3 bounds() const override { return bounds_; }
    double sample_free_flight(const Ray& ray, double tmax, Rng& rng) const override;
    double transmittance(const Ray& ray, double tmax, Rng& rng) const override;
    double sigma_t(const Vec3& p) const override;
    // Inside the shape; a sphere's lens (any overlap); a box crossed through the faces of one axis
    // (caps), or of more around x (scene/media/ball_clip_moments.h).
    bool ball_integral(const Vec3& x, double r, double& integral) const override;
    // A sphere's lens (any overlap); a box around x (any faces, edges and corners in reach).
    bool ball_moments(const Vec3& x, double r, double& m0, Vec3& m1, Eigen::Matrix3d& m2) const override;
    void majorant_pieces(const Ray& ray, double tmax, const MajorantVisitor& visit) const override;   // exact here
    void optical_depth_profile(const Ray& ray, double tmax, OpticalDepthProfile& out) const override;   // one piece
    std::string describe() const override;

    // Whether B(x, r) lies inside the shape, where sigma_t is sigma_t_value() throughout.
    bool contains_ball(const Vec3& x, double r) const;
    double sigma_t_value() const { return sigma_t_; }

    // The parameter interval of the ray inside the shape, clipped to [0, tmax].
    bool clip(const Ray& ray, double tmax, double& t0, double& t1) const;

private:
    HomogeneousMedium(Shape shape, const Bounds3& bounds, const Vec3& center, double radius, double sigma_t,
                      const Rgb& albedo, double g);
    Shape shape_;
    Bounds3 bounds_;
    Vec3 center_;
    double radius_;
    double sigma_t_;
};

std::unique_ptr<Medium> make_homogeneous_medium(Params& p);

}  // namespace vpm
