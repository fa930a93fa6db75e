// type = "quad": center, u, v (half edges: corners center +- u +- v, as for quad shapes), radiance,
// two_sided (false); a Lambertian emitter on the side of u x v (both sides when two_sided). Not
// geometry: camera and scattered rays pass through it; it is seen through next-event estimation.
#include <sstream>

#include "core/sampling.h"
#include "scene/light_registry.h"
#include "scene/params.h"

namespace vpm {

namespace {

class QuadLight : public Light {
public:
    QuadLight(const Vec3& center, const Vec3& edge_u, const Vec3& edge_v, const Rgb& radiance, bool two_sided)
        : corner_(center - 0.5 * edge_u - 0.5 * edge_v), edge_u_(edge_u), edge_v_(edge_v),
          normal_(edge_u.cross(edge_v).normalized()), area_(edge_u.cross(edge_v).norm()),
          radiance_(radiance), two_sided_(two_sided) {}

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
        out.weight = radiance_ * (cos_light * area_ / dist2);   // Le / pdf_solid_angle
        return true;
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
};

}  // namespace

std::unique_ptr<Light> make_quad_light(Params& p) {
    const Range non_negative = Range::at_least(0.0);
    const Vec3 center = p.vec3("center");
    // Half edges, as for quad shapes: the corners are center +- u +- v.
    const Vec3 u = p.vec3("u");
    const Vec3 v = p.vec3("v");
    if (u.cross(v).norm() == 0.0) p.fail("v", "u and v must span a non-zero area");
    const Rgb radiance = p.rgb("radiance", non_negative);
    return std::make_unique<QuadLight>(center, 2.0 * u, 2.0 * v, radiance, p.boolean("two_sided", false));
}

}  // namespace vpm
