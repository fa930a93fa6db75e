#include "scene/media/homogeneous_medium.h"

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

double HomogeneousMedium::sigma_t(const Vec3& p) const {
    const bool inside = shape_ == Shape::box ? bounds_.contains(p) : (p - center_).squaredNorm() <= radius_ * radius_;
    return inside ? sigma_t_ : 0.0;
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
        if ((hi.array() <= lo.array()).any()) p.fail("max", "must exceed min in every axis");
        return std::make_unique<HomogeneousMedium>(HomogeneousMedium::box(lo, hi, sigma_t, albedo, g));
    }
    const Vec3 center = p.vec3("center", Vec3::Zero());
    const double radius = p.real("radius", 1.0, Range::positive());
    return std::make_unique<HomogeneousMedium>(HomogeneousMedium::sphere(center, radius, sigma_t, albedo, g));
}

}  // namespace vpm
