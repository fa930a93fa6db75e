// type = "quad": center, u, v (half edges: corners center +- u +- v, as for quad shapes), radiance,
// two_sided (false); a Lambertian emitter on the side of u x v (both sides when two_sided). It is
// geometry (light.h): rays that meet it see its radiance (zero on the back of a one-sided quad) and
// stop there, as on a black surface. Next-event estimation samples it uniformly by area.
//
// Photons: a quad much larger than its distance to what it can light (media, shapes and
// the other area lights: its target) sent nearly all its photons from points and in directions that
// miss the target (half-edge 1e4 over a unit sphere: the photon map 24% dark; from 1e6 the light was
// lost). Such a quad emits from a mixture: with probability 1 - a the classic way (uniform point,
// cosine direction, pdf cos / (pi A)), with probability a = 1/2 a point found from the target's
// centre c (a direction uniform over the hemisphere towards the plane, density h / (2 pi |x - c|^3)
// on the plane; a miss of the quad is a photon of zero power) and a direction uniform in the cone
// around the target's bounding sphere (emission_cone.h). Each photon carries L cos / p_mix(x, w),
// p_mix the mixture's density, so the emitted power stays L pi A in expectation (one-sample MIS).
// A quad far from its target (further than twice their radii together) mixes the cosine law with
// a direction uniform in the cone from the emitting point towards the target, as sphere lights do
// (a 0.5 x 0.5 quad 9 units from a unit box sent nearly all its photons past it).
// "Large" is decided by geometry alone: the quad's half extent exceeds the target centre's height
// over its plane plus the target's radius; other quads emit exactly as before. A large quad's
// next-event estimation is a mixture too: half its samples uniform by area, half a direction
// uniform over the hemisphere towards the quad's plane (solid-angle pdf 1 / 2 pi; a miss weighs 0),
// pdf_incident the mixture's density. Area sampling alone put nearly every sample of a 1e4 quad
// at grazing distances: unbiased, but the single scattering it estimated was 25% low at 64 spp.
// Precision ends where the plane's self-intersection epsilon, 1e-9 of the quad's extent, reaches the
// scene's distance to it: a half-edge of ~1e9 over a scene 2 units away is then not met at all.
#include <cmath>
#include <limits>
#include <sstream>

#include "core/sampling/sampling.h"
#include "scene/lights/emission_cone.h"
#include "scene/lights/light_registry.h"
#include "config/params.h"

namespace vpm {

namespace {

class QuadLight : public Light {
public:
    QuadLight(const Vec3& center, const Vec3& edge_u, const Vec3& edge_v, const Rgb& radiance, bool two_sided)
        : corner_(center - 0.5 * edge_u - 0.5 * edge_v), edge_u_(edge_u), edge_v_(edge_v),
          normal_(edge_u.cross(edge_v).normalized()), area_(edge_u.cross(edge_v).norm()),
          radiance_(radiance), two_sided_(two_sided),
          extent_(edge_u.cwiseAbs().maxCoeff() + edge_v.cwiseAbs().maxCoeff()) {}

    bool sample_incident(const Vec3& x, Rng& rng, LightSample& out) const override {
        const double u1 = rng.uniform(), u2 = rng.uniform();
        if (large_ && rng.uniform() < kAimedShare) {   // a direction towards the plane, uniform
            const double side = (x - corner_).dot(normal_) >= 0.0 ? 1.0 : -1.0;
            const double z = u1, r = std::sqrt(std::max(0.0, 1.0 - z * z)), phi = 2.0 * kPi * u2;
            const Vec3 wi = Frame(Vec3(-side * normal_)).to_world(Vec3(r * std::cos(phi), r * std::sin(phi), z)).normalized();
            EmitterHit h;
            if (!intersect(Ray{x, wi}, kInfinity, h) || (h.radiance == 0.0).all()) return false;
            out.wi = wi;
            out.distance = h.t;
            out.pdf = mixture_pdf(h.t * h.t / (std::abs(wi.dot(normal_)) * area_));
            out.weight = radiance_ / out.pdf;
            return true;
        }
        const Vec3 p = corner_ + u1 * edge_u_ + u2 * edge_v_;
        const Vec3 d = p - x;
        const double dist2 = d.squaredNorm();
        if (dist2 == 0.0) return false;
        const double dist = std::sqrt(dist2);
        const Vec3 wi = d / dist;
        double cos_light = -wi.dot(normal_);
        if (two_sided_) cos_light = std::abs(cos_light);
        if (cos_light <= 0.0) return false;
        out.wi = wi;
        out.distance = dist;
        out.pdf = mixture_pdf(dist2 / (cos_light * area_));   // area pdf 1/A turned into solid angle
        out.weight = radiance_ / out.pdf;
        return true;
    }
    double pdf_incident(const Vec3& x, const Vec3& wi) const override {
        EmitterHit h;
        if (!intersect(Ray{x, wi}, kInfinity, h) || (h.radiance == 0.0).all()) return 0.0;
        return mixture_pdf(h.t * h.t / (std::abs(wi.dot(normal_)) * area_));
    }
    bool intersect(const Ray& ray, double tmax, EmitterHit& hit) const override {
        const double denom = ray.dir.dot(normal_);
        if (denom == 0.0) return false;
        const Vec3 to_corner = corner_ - ray.origin;
        const double height = -to_corner.dot(normal_);   // signed distance of the origin to the plane
        // Photons leave the quad from a point on its plane: such rays do not meet it again.
        if (std::abs(height) <= 1e-9 * (to_corner.cwiseAbs().maxCoeff() + extent_)) return false;
        const double t = -height / denom;
        if (!(t > 0.0) || !(t < tmax)) return false;
        // Parallelogram coordinates of the hit: w = a u + b v with a, b in [0, 1].
        const Vec3 w = ray.at(t) - corner_;
        const Vec3 n_unnorm = edge_u_.cross(edge_v_);
        const double inv = 1.0 / n_unnorm.squaredNorm();
        const double a = w.cross(edge_v_).dot(n_unnorm) * inv;
        const double b = edge_u_.cross(w).dot(n_unnorm) * inv;
        if (a < 0.0 || a > 1.0 || b < 0.0 || b > 1.0) return false;
        hit.t = t;
        hit.normal = denom < 0.0 ? normal_ : Vec3(-normal_);
        hit.radiance = (denom < 0.0 || two_sided_) ? radiance_ : Rgb::Zero();
        return true;
    }
    Bounds3 bounds() const override {
        Bounds3 b;
        for (double a : {0.0, 1.0})
            for (double c : {0.0, 1.0}) b.extend(Vec3(corner_ + a * edge_u_ + c * edge_v_));
        return b;
    }
    EmissionSample sample_emission(Rng& rng) const override {
        const double u1 = rng.uniform(), u2 = rng.uniform(), u3 = rng.uniform(), u4 = rng.uniform();
        Vec3 n = normal_;
        double scale = 1.0;
        if (two_sided_) {
            if (rng.uniform() < 0.5) n = -n;
            scale = 2.0;
        }
        const double height = (target_centre_ - corner_).dot(n);   // of the target's centre over this side
        if (!aimed(height)) {
            const Vec3 p = corner_ + u1 * edge_u_ + u2 * edge_v_;
            if (!far(height)) {
                const Vec3 dir = Frame(n).to_world(sample_cosine_hemisphere(u3, u4)).normalized();
                return {Ray{p, dir}, radiance_ * (kPi * area_ * scale)};
            }
            const AimedDirection a = aim_cosine_or_cone(p, n, target_, kAimedShare, rng.uniform(), u3, u4);
            return {Ray{p, a.dir}, radiance_ * (a.weight * area_ * scale)};
        }
        Vec3 p, dir;
        if (rng.uniform() < kAimedShare) {   // a point seen from the target's centre, a direction into its cone
            const double z = u1, r = std::sqrt(std::max(0.0, 1.0 - z * z)), phi = 2.0 * kPi * u2;
            const Vec3 down = Frame(-n).to_world(Vec3(r * std::cos(phi), r * std::sin(phi), z));
            const double t = height / down.dot(-n);
            p = target_centre_ + t * down;
            const Vec3 w = p - corner_;
            const Vec3 n_unnorm = edge_u_.cross(edge_v_);
            const double inv = 1.0 / n_unnorm.squaredNorm();
            const double a = w.cross(edge_v_).dot(n_unnorm) * inv, b = edge_u_.cross(w).dot(n_unnorm) * inv;
            if (!(t > 0.0) || !std::isfinite(t) || a < 0.0 || a > 1.0 || b < 0.0 || b > 1.0)   // missed the quad
                return {Ray{corner_, n}, Rgb::Zero()};
            p = corner_ + a * edge_u_ + b * edge_v_;   // on the plane exactly
            dir = EmissionCone::towards(p, target_).sample(u3, u4);
        } else {
            p = corner_ + u1 * edge_u_ + u2 * edge_v_;
            dir = Frame(n).to_world(sample_cosine_hemisphere(u3, u4)).normalized();
        }
        const double cos = dir.dot(n);
        if (!(cos > 0.0)) return {Ray{p, dir}, Rgb::Zero()};
        const double classic = cos / (kPi * area_);
        const double d = (p - target_centre_).norm();
        const EmissionCone cone = EmissionCone::towards(p, target_);
        const double aimed_pdf = height / (2.0 * kPi * d * d * d) * (cone.contains(dir) ? 1.0 / cone.solid_angle() : 0.0);
        const double pdf = (1.0 - kAimedShare) * classic + kAimedShare * aimed_pdf;
        return {Ray{p, dir}, radiance_ * (cos * scale / pdf)};
    }
    void set_scene_bounds(const Bounds3& target) override {
        target_ = target;
        if (target.empty()) return;
        target_centre_ = 0.5 * (target.lo + target.hi);
        target_radius_ = 0.5 * (target.hi - target.lo).norm();
        const double height = (target_centre_ - corner_).dot(normal_);
        large_ = aimed(height) || (two_sided_ && aimed(-height));
    }
    Rgb power() const override { return radiance_ * (kPi * area_ * (two_sided_ ? 2.0 : 1.0)); }
    std::string describe() const override {
        std::ostringstream s;
        s << "quad light, area " << area_ << ", normal (" << normal_.transpose() << ")"
          << (two_sided_ ? ", two-sided" : "") << ", radiance " << format_rgb(radiance_);
        return s.str();
    }

private:
    Vec3 corner_, edge_u_, edge_v_, normal_;
    double area_;
    Rgb radiance_;
    bool two_sided_;
    double extent_;   // size scale for the self-intersection epsilon
    Bounds3 target_;  // what this light can light (set_scene_bounds); empty: classic emission
    Vec3 target_centre_ = Vec3::Zero();
    double target_radius_ = 0.0;
    bool large_ = false;   // aimed emission and mixture NEE (see the top of the file)
    static constexpr double kAimedShare = 0.5;

    // Solid-angle pdf of next-event estimation given that of area sampling.
    double mixture_pdf(double area_pdf) const {
        return large_ ? (1.0 - kAimedShare) * area_pdf + kAimedShare / (2.0 * kPi) : area_pdf;
    }

    // Whether this side, not large, is far from the target (its centre in front of it): photons
    // from the cosine law or a cone towards it. The quad's radius is taken as the sum of its half
    // diagonals (at least its circumradius).
    bool far(double height) const {
        return height > 0.0 && far_from_target(corner_ + 0.5 * (edge_u_ + edge_v_),
                                                0.5 * (edge_u_ + edge_v_).norm() + 0.5 * (edge_u_ - edge_v_).norm(), target_);
    }
    // Whether this side emits from the mixture: the target's centre in front of it and the quad
    // larger than the target's distance from its plane plus the target's radius.
    bool aimed(double height) const {
        return !target_.empty() && height > 0.0 && 0.5 * extent_ > height + target_radius_;
    }
};

}  // namespace

std::unique_ptr<Light> make_quad_light(Params& p) {
    const Vec3 center = p.vec3("center");
    // Half edges, as for quad shapes: the corners are center +- u +- v.
    const Vec3 u = p.vec3("u");
    const Vec3 v = p.vec3("v");
    if (u.cross(v).norm() == 0.0) p.fail("v", "u and v must span a non-zero area");
    // The area and its inverse (next-event estimation's pdf) must be normal finite doubles.
    const double area = (2.0 * u).cross(2.0 * v).norm();
    if (!(area >= std::numeric_limits<double>::min()) || !std::isfinite(area))
        p.fail("u", "the quad's area |2u x 2v| = " + format_value(area) +
                        " is not a normal finite double, so its sampling pdf 1 / area cannot be represented");
    const Rgb radiance = p.rgb("radiance", emission_range());
    auto light = std::make_unique<QuadLight>(center, 2.0 * u, 2.0 * v, radiance, p.boolean("two_sided", false));
    require_finite_power(p, "u", *light, "radiance x pi x area " + format_value(area));
    return light;
}

}  // namespace vpm
