// type = "quad": center, u, v (half edges: corners center +- u +- v, as for quad shapes), radiance,
// two_sided (false); a Lambertian emitter on the side of u x v (both sides when two_sided). It is
// geometry (light.h): rays that meet it see its radiance (zero on the back of a one-sided quad) and
// stop there, as on a black surface. Next-event estimation samples it uniformly by area.
#include <cmath>
#include <limits>
#include <sstream>

#include "core/sampling.h"
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
        out.pdf = dist2 / (cos_light * area_);   // area pdf 1/A turned into solid angle
        out.weight = radiance_ / out.pdf;
        return true;
    }
    double pdf_incident(const Vec3& x, const Vec3& wi) const override {
        EmitterHit h;
        if (!intersect(Ray{x, wi}, kInfinity, h) || (h.radiance == 0.0).all()) return 0.0;
        return h.t * h.t / (std::abs(wi.dot(normal_)) * area_);
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
        const Vec3 p = corner_ + u1 * edge_u_ + u2 * edge_v_;
        const Vec3 dir = Frame(n).to_world(sample_cosine_hemisphere(u3, u4)).normalized();
        return {Ray{p, dir}, radiance_ * (kPi * area_ * scale)};
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
