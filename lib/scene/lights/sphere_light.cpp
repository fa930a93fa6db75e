// type = "sphere": center, radius (> 0), radiance; a Lambertian emitter over the outside of a
// sphere. It is geometry (light.h): rays that meet it from outside see its radiance and stop there;
// inside it is dark (it emits outwards only, as its photons leave it, so points inside receive
// nothing and a camera inside sees black). Next-event estimation samples the cone of directions
// the sphere subtends from the point (uniform in solid angle, pdf 1 / (2 pi (1 - cos theta_max))),
// which is exact in direction and wastes no sample on the far side. pbrt falls back to area
// sampling for points inside; here nothing inside is lit, so no fallback is needed.
// Photons: a sphere light far from what it can light (its target: media, shapes, other area
// lights, more than twice their bounding radius plus its own away) emits half its photons from the
// cosine law and half uniformly in the cone from the surface point towards the target, each with
// power L cos A / p_mix (one-sample MIS, as the large quad's): L pi A in expectation. Cosine emission
// alone sent 99.5% of the photons of a 0.3-radius light 9 units from a unit box into empty space.
// Near what it lights, where most directions reach nothing, half of its photons follow a guide
// over directions instead (scene/emission_guides.h; guided_emission below).
#include <cmath>
#include <limits>
#include <sstream>

#include "core/sampling/sampling.h"
#include "scene/lights/emission_cone.h"
#include "scene/lights/guided_emission.h"
#include "scene/lights/light_registry.h"
#include "config/params.h"

namespace vpm {

namespace {

class SphereLight : public Light {
public:
    SphereLight(const Vec3& center, double radius, const Rgb& radiance)
        : center_(center), radius_(radius), radiance_(radiance) {}

    bool sample_incident(const Vec3& x, Rng& rng, LightSample& out) const override {
        const double u1 = rng.uniform(), u2 = rng.uniform();
        double dist, one_minus_cos_max;
        if (!cone(x, dist, one_minus_cos_max)) return false;
        // Uniform in the cone; 1 - cos theta is kept apart from cos theta so that a small, far
        // sphere (1 - cos theta_max ~ r^2 / 2 d^2) keeps its precision.
        const double one_minus_cos = u1 * one_minus_cos_max;
        const double cos_theta = 1.0 - one_minus_cos;
        const double sin2 = std::max(0.0, one_minus_cos * (2.0 - one_minus_cos));
        const double phi = 2.0 * kPi * u2;
        const double sin_theta = std::sqrt(sin2);
        const Vec3 axis = (center_ - x) / dist;
        out.wi = Frame(axis).to_world(Vec3(sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta)).normalized();
        // Near intersection of the sampled direction with the sphere (at the rim the root is 0).
        out.distance = std::max(0.0, dist * cos_theta - std::sqrt(std::max(0.0, radius_ * radius_ - dist * dist * sin2)));
        out.pdf = 1.0 / (2.0 * kPi * one_minus_cos_max);
        out.weight = radiance_ / out.pdf;
        return true;
    }
    double pdf_incident(const Vec3& x, const Vec3& wi) const override {
        double dist, one_minus_cos_max;
        if (!cone(x, dist, one_minus_cos_max)) return 0.0;
        EmitterHit h;
        if (!intersect(Ray{x, wi}, kInfinity, h)) return 0.0;
        return 1.0 / (2.0 * kPi * one_minus_cos_max);
    }
    bool intersect(const Ray& ray, double tmax, EmitterHit& hit) const override {
        const Vec3 oc = ray.origin - center_;
        const double b = oc.dot(ray.dir);
        // r^2 - (distance of the line from the centre)^2, without the cancellation of b^2 - c.
        const double disc = radius_ * radius_ - (oc - b * ray.dir).squaredNorm();
        if (disc < 0.0) return false;
        const double c = oc.squaredNorm() - radius_ * radius_;
        const double q = -b - std::copysign(std::sqrt(disc), b);
        double t0 = q, t1 = q != 0.0 ? c / q : 0.0;
        if (t0 > t1) std::swap(t0, t1);
        // Photons leave from a point on the sphere: the root at ~0 is that point, not a hit.
        const double eps = 1e-9 * (oc.norm() + radius_);
        const double t = t0 > eps ? t0 : t1;
        if (!(t > eps) || !(t < tmax)) return false;
        const Vec3 n = (ray.at(t) - center_).normalized();
        const bool outside = n.dot(ray.dir) < 0.0;
        hit.t = t;
        hit.normal = outside ? n : Vec3(-n);
        hit.radiance = outside ? radiance_ : Rgb::Zero();
        return true;
    }
    // Uniform point on the sphere, cosine-distributed direction outwards: power L pi A.
    EmissionSample sample_emission(Rng& rng) const override {
        const double u1 = rng.uniform(), u2 = rng.uniform(), u3 = rng.uniform(), u4 = rng.uniform();
        if (guided_.active()) return guided_emission(rng.uniform(), u1, u2, u3, u4);
        const Vec3 n = sample_uniform_sphere(u1, u2);
        const Vec3 p = center_ + radius_ * n;
        if (!aimed_) {
            const Vec3 dir = Frame(n).to_world(sample_cosine_hemisphere(u3, u4)).normalized();
            return {Ray{p, dir}, power()};
        }
        const AimedDirection a = aim_cosine_or_cone(p, n, target_, kAimedShare, rng.uniform(), u3, u4);
        return {Ray{p, a.dir}, radiance_ * (a.weight * area())};
    }
    // Aim when what the light can light is far from it; near or overlapping, emit as before.
    void set_scene_bounds(const Bounds3& target) override {
        target_ = target;
        aimed_ = far_from_target(center_, radius_, target);
    }
    Rgb power() const override { return radiance_ * (kPi * area()); }
    bool guide_origin(Vec3& origin, double& start) const override {
        if (aimed_) return false;   // far: the cone towards the target is aimed already
        origin = center_;
        start = radius_;
        return true;
    }
    // Cosine emission from uniform points of a sphere leaves it isotropically.
    double emission_direction_pdf(const Vec3&) const override { return kInv4Pi; }
    void set_emission_guide(std::shared_ptr<const DirectionGuide> guide, double share) override {
        guided_.set(std::move(guide), share);
    }
    Bounds3 bounds() const override {
        Bounds3 b;
        b.extend(Vec3(center_ - Vec3::Constant(radius_)));
        b.extend(Vec3(center_ + Vec3::Constant(radius_)));
        return b;
    }
    std::string describe() const override {
        std::ostringstream s;
        s << "sphere light at (" << center_.transpose() << "), radius " << radius_ << ", radiance " << format_rgb(radiance_);
        return s.str();
    }

private:
    double area() const { return 4.0 * kPi * radius_ * radius_; }
    // A photon of the mixture of the cosine law (density cos / (pi A) over point and direction) and
    // the guide: a direction w from the guide, then a point with density cos / (pi r^2) over the half
    // of the sphere facing w (uniform on the disc perpendicular to w, lifted onto the sphere), a joint
    // density 4 cos pdf_guide(w) / A. Over the mixture, L cos / p = L A / ((1 - s) / pi + 4 s pdf_guide(w)):
    // L pi A on average, as before.
    EmissionSample guided_emission(double choice, double u1, double u2, double u3, double u4) const {
        const double share = guided_.share();
        Vec3 p, dir;
        if (choice < share) {
            dir = guided_.guide().sample(u1, u2);
            const Eigen::Vector2d d = sample_uniform_disc(u3, u4);
            const Frame f(dir);
            p = center_ + radius_ * (d.x() * f.s + d.y() * f.t + std::sqrt(std::max(0.0, 1.0 - d.squaredNorm())) * dir);
        } else {
            const Vec3 n = sample_uniform_sphere(u1, u2);
            p = center_ + radius_ * n;
            dir = Frame(n).to_world(sample_cosine_hemisphere(u3, u4)).normalized();
        }
        const double density = (1.0 - share) / kPi + 4.0 * share * guided_.guide().pdf(dir);
        return {Ray{p, dir}, radiance_ * (area() / density)};
    }
    GuidedEmission guided_;   // inactive: cosine (or aimed) emission only
    Bounds3 target_;       // what this light can light (set_scene_bounds)
    bool aimed_ = false;   // photons from the mixture with a cone towards target_ (sample_emission)
    static constexpr double kAimedShare = 0.5;
    // The cone the sphere subtends from x: distance to the centre and 1 - cos theta_max (computed
    // as sin^2 / (1 + cos) against cancellation). False when x is inside or on the sphere.
    bool cone(const Vec3& x, double& dist, double& one_minus_cos_max) const {
        const double d2 = (center_ - x).squaredNorm();
        if (!(d2 > radius_ * radius_)) return false;
        dist = std::sqrt(d2);
        const double sin2_max = radius_ * radius_ / d2;
        one_minus_cos_max = sin2_max / (1.0 + std::sqrt(std::max(0.0, 1.0 - sin2_max)));
        return one_minus_cos_max > 0.0;
    }

    Vec3 center_;
    double radius_;
    Rgb radiance_;
};

}  // namespace

std::unique_ptr<Light> make_sphere_light(Params& p) {
    const Vec3 center = p.vec3("center");
    const double radius = p.real("radius", Range::positive());
    // r^2 enters the area, the intersection and the cone NEE samples: it must be a normal finite double.
    if (!(radius * radius >= std::numeric_limits<double>::min()) || !std::isfinite(4.0 * kPi * radius * radius))
        p.fail("radius", "radius " + format_value(radius) + " is out of range: its area 4 pi r^2 is not a normal finite "
                         "double (allowed: about 1.5e-154 to 2.8e153)");
    const Rgb radiance = p.rgb("radiance", emission_range());
    auto light = std::make_unique<SphereLight>(center, radius, radiance);
    require_finite_power(p, "radius", *light, "radiance x pi x 4 pi r^2");
    return light;
}

}  // namespace vpm
