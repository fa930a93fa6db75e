#include "scene/media/homogeneous_medium.h"

#include "scene/media/ball_clip_moments.h"

#include <algorithm>
#include <sstream>

namespace vpm {

HomogeneousMedium::HomogeneousMedium(Shape shape, const Bounds3& bounds, const Vec3& center, double radius,
                                     double sigma_t, const Rgb& albedo, double g)
    : Medium(albedo, g), shape_(shape), bounds_(bounds), center_(center), radius_(radius), sigma_t_(sigma_t) {}

HomogeneousMedium HomogeneousMedium::box(const Vec3& lo, const Vec3& hi, double sigma_t, const Rgb& albedo, double g) {
    return HomogeneousMedium(Shape::box, Bounds3{lo, hi}, 0.5 * (lo + hi), 0.0, sigma_t, albedo, g);
}

HomogeneousMedium HomogeneousMedium::sphere(const Vec3& center, double radius, double sigma_t, const Rgb& albedo,
                                            double g) {
    const Vec3 r = Vec3::Constant(radius);
    return HomogeneousMedium(Shape::sphere, Bounds3{center - r, center + r}, center, radius, sigma_t, albedo, g);
}

bool HomogeneousMedium::clip(const Ray& ray, double tmax, double& t0, double& t1) const {
    if (shape_ == Shape::box) return bounds_.intersect(ray, tmax, t0, t1);
    // Sphere: |o + t d - c|^2 = r^2 with |d| = 1. The half-chord is computed from the distance of
    // the centre to the ray's line, which stays accurate for rays starting far away.
    const Vec3 oc = ray.origin - center_;
    const double b = oc.dot(ray.dir);
    const Vec3 closest = oc - b * ray.dir;
    const double h2 = radius_ * radius_ - closest.squaredNorm();
    if (h2 < 0.0) return false;
    const double h = std::sqrt(h2);
    t0 = std::max(0.0, -b - h);
    t1 = std::min(tmax, -b + h);
    return t0 < t1;
}

bool HomogeneousMedium::contains_ball(const Vec3& x, double r) const {
    if (shape_ == Shape::sphere) return (x - center_).norm() + r <= radius_;
    const Vec3 half = Vec3::Constant(r);
    return bounds_.contains(x - half) && bounds_.contains(x + half);
}

double HomogeneousMedium::sample_free_flight(const Ray& ray, double tmax, Rng& rng) const {
    double t0, t1;
    if (sigma_t_ <= 0.0 || !clip(ray, tmax, t0, t1)) return kInfinity;
    // -log1p(-u) is exact for small u and finite for u in [0, 1).
    const double t = t0 - std::log1p(-rng.uniform()) / sigma_t_;
    return t < t1 ? t : kInfinity;
}

double HomogeneousMedium::transmittance(const Ray& ray, double tmax, Rng&) const {
    double t0, t1;
    if (sigma_t_ <= 0.0 || !clip(ray, tmax, t0, t1)) return 1.0;
    return std::exp(-sigma_t_ * (t1 - t0));
}

void HomogeneousMedium::majorant_pieces(const Ray& ray, double tmax, const MajorantVisitor& visit) const {
    double t0, t1;
    if (sigma_t_ > 0.0 && clip(ray, tmax, t0, t1)) visit(t0, t1, sigma_t_);
}

void HomogeneousMedium::optical_depth_profile(const Ray& ray, double tmax, OpticalDepthProfile& out) const {
    out.reset(sigma_t_);
    double t0, t1;
    if (sigma_t_ > 0.0 && clip(ray, tmax, t0, t1)) out.add_constant(t0, t1, 1.0);
}

double HomogeneousMedium::sigma_t(const Vec3& p) const {
    const bool inside = shape_ == Shape::box ? bounds_.contains(p) : (p - center_).squaredNorm() <= radius_ * radius_;
    return inside ? sigma_t_ : 0.0;
}

bool HomogeneousMedium::ball_integral(const Vec3& x, double r, double& integral) const {
    const double ball = (4.0 / 3.0) * kPi * r * r * r;
    if (shape_ == Shape::sphere) {
        // Volume of the intersection of two balls (radii R, r, centres d apart).
        const double R = radius_, d = (x - center_).norm();
        double v;
        if (d + r <= R) v = ball;
        else if (d + R <= r) v = (4.0 / 3.0) * kPi * R * R * R;
        else if (d >= R + r) v = 0.0;
        else v = kPi * (R + r - d) * (R + r - d) * (d * d + 2.0 * d * r - 3.0 * r * r + 2.0 * d * R + 6.0 * r * R - 3.0 * R * R) / (12.0 * d);
        integral = sigma_t_ * v;
        return true;
    }
    // Box: the ball minus the caps beyond the faces it crosses, when they are the two faces of one
    // axis; caps of different axes may overlap near edges and corners, where the inclusion-exclusion
    // of ball_clip_moments.h takes over (x inside the box; else the caller integrates).
    int crossing_axis = -1;
    double caps = 0.0;
    for (int a = 0; a < 3; ++a) {
        const double below = x[a] - bounds_.lo[a], above = bounds_.hi[a] - x[a];   // signed distances to the faces
        if (below <= -r || above <= -r) {
            integral = 0.0;   // the ball is entirely outside this slab
            return true;
        }
        if (below >= r && above >= r) continue;
        if (crossing_axis >= 0) {   // an edge or a corner in reach: inclusion-exclusion of the caps
            ClipMoments m;
            if (!ball_box_moments(r, bounds_.lo - x, bounds_.hi - x, m)) return false;
            integral = sigma_t_ * m.m0;
            return true;
        }
        crossing_axis = a;
        for (const double dist : {below, above}) {
            if (dist >= r) continue;
            const double h = r - dist;   // cap height beyond the face, in (0, 2r)
            caps += kPi * h * h * (3.0 * r - h) / 3.0;
        }
    }
    integral = sigma_t_ * std::max(0.0, ball - caps);
    return true;
}

bool HomogeneousMedium::ball_moments(const Vec3& x, double r, double& m0, Vec3& m1, Eigen::Matrix3d& m2) const {
    ClipMoments m;
    if (shape_ == Shape::sphere) m = ball_ball_moments(r, center_ - x, radius_);
    else if (!ball_box_moments(r, bounds_.lo - x, bounds_.hi - x, m)) return false;
    m0 = sigma_t_ * m.m0;
    m1 = sigma_t_ * m.m1;
    m2 = sigma_t_ * m.m2;
    return true;
}

std::string HomogeneousMedium::describe() const {
    std::ostringstream s;
    s << "homogeneous " << (shape_ == Shape::box ? "box" : "sphere") << " [" << bounds_.lo.transpose() << "] - ["
      << bounds_.hi.transpose() << "], sigma_t " << sigma_t_ << ", albedo [" << albedo_.transpose() << "], g " << g_;
    return s.str();
}

std::unique_ptr<Medium> make_homogeneous_medium(Params& p) {
    const std::string shape = p.choice("shape", "box", {"box", "sphere"});
    const double sigma_t = p.real("sigma_t_scale", 1.0, Range::at_least(0.0));
    const Rgb albedo = p.rgb("albedo", Rgb::Constant(0.8), Range::closed(0.0, 1.0));
    const double g = p.real("g", 0.0, Range::open(-1.0, 1.0));
    if (shape == "box") {
        const Vec3 lo = p.vec3("min", Vec3::Constant(-1.0));
        const Vec3 hi = p.vec3("max", Vec3::Constant(1.0));
        if ((hi.array() <= lo.array()).any())
            p.fail("max", "must exceed " + p.path_of("min") + " (" + p.where("min") + ") in every axis");
        return std::make_unique<HomogeneousMedium>(HomogeneousMedium::box(lo, hi, sigma_t, albedo, g));
    }
    const Vec3 center = p.vec3("center", Vec3::Zero());
    const double radius = p.real("radius", 1.0, Range::positive());
    return std::make_unique<HomogeneousMedium>(HomogeneousMedium::sphere(center, radius, sigma_t, albedo, g));
}

}  // namespace vpm
