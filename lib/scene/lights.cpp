#include "scene/lights.h"

#include <sstream>

#include "core/sampling.h"
#include "scene/emission_bounds.h"

namespace vpm {

namespace {

std::string rgb_string(const Rgb& c) {
    std::ostringstream s;
    s << "[" << c[0] << ", " << c[1] << ", " << c[2] << "]";
    return s.str();
}

class PointLight : public Light {
public:
    PointLight(const Vec3& position, const Rgb& intensity) : position_(position), intensity_(intensity) {}

    bool sample_incident(const Vec3& x, Rng&, LightSample& out) const override {
        const Vec3 d = position_ - x;
        const double dist2 = d.squaredNorm();
        if (dist2 == 0.0) return false;
        out.distance = std::sqrt(dist2);
        out.wi = d / out.distance;
        out.weight = intensity_ / dist2;
        return true;
    }
    EmissionSample sample_emission(Rng& rng) const override {
        const double u1 = rng.uniform(), u2 = rng.uniform();
        return {Ray{position_, sample_uniform_sphere(u1, u2)}, intensity_ * (4.0 * kPi)};
    }
    Rgb power() const override { return intensity_ * (4.0 * kPi); }
    std::string describe() const override {
        std::ostringstream s;
        s << "point light at (" << position_.transpose() << "), intensity " << rgb_string(intensity_);
        return s.str();
    }

private:
    Vec3 position_;
    Rgb intensity_;
};

// Constant intensity inside a cone, zero outside (no falloff ring: keeps the emitted power exact).
class SpotLight : public Light {
public:
    SpotLight(const Vec3& position, const Vec3& axis, const Rgb& intensity, double cos_max)
        : position_(position), frame_(axis), intensity_(intensity), cos_max_(cos_max) {}

    bool sample_incident(const Vec3& x, Rng&, LightSample& out) const override {
        const Vec3 d = x - position_;
        const double dist2 = d.squaredNorm();
        if (dist2 == 0.0) return false;
        const double dist = std::sqrt(dist2);
        if (d.dot(frame_.n) / dist < cos_max_) return false;
        out.distance = dist;
        out.wi = -d / dist;
        out.weight = intensity_ / dist2;
        return true;
    }
    EmissionSample sample_emission(Rng& rng) const override {
        const double u1 = rng.uniform(), u2 = rng.uniform();
        const Vec3 dir = frame_.to_world(sample_uniform_cone(u1, u2, cos_max_)).normalized();
        return {Ray{position_, dir}, power()};
    }
    Rgb power() const override { return intensity_ * (2.0 * kPi * (1.0 - cos_max_)); }
    std::string describe() const override {
        std::ostringstream s;
        s << "spot light at (" << position_.transpose() << ") towards (" << frame_.n.transpose()
          << "), half-angle " << std::acos(cos_max_) * 180.0 / kPi << " deg, intensity " << rgb_string(intensity_);
        return s.str();
    }

private:
    Vec3 position_;
    Frame frame_;
    Rgb intensity_;
    double cos_max_;
};

class DirectionalLight : public Light {
public:
    DirectionalLight(const Vec3& direction, const Rgb& irradiance) : dir_(direction), irradiance_(irradiance) {}

    bool sample_incident(const Vec3&, Rng&, LightSample& out) const override {
        out.wi = -dir_;
        out.distance = kInfinity;
        out.weight = irradiance_;
        return true;
    }
    EmissionSample sample_emission(Rng& rng) const override {
        const double u1 = rng.uniform(), u2 = rng.uniform(), u3 = rng.uniform();
        return {Ray{bounds_.sample_origin(dir_, u1, u2, u3), dir_}, power()};
    }
    // Only the light crossing the silhouette of what can be lit (emission_bounds.h).
    Rgb power() const override { return irradiance_ * bounds_.projected_area(dir_); }
    void set_scene_bounds(const Bounds3& b) override { bounds_.set(b); }
    std::string describe() const override {
        std::ostringstream s;
        s << "directional light along (" << dir_.transpose() << "), irradiance " << rgb_string(irradiance_);
        return s.str();
    }

private:
    Vec3 dir_;
    Rgb irradiance_;
    EmissionBounds bounds_;
};

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
          << (two_sided_ ? ", two-sided" : "") << ", radiance " << rgb_string(radiance_);
        return s.str();
    }

private:
    Vec3 corner_, edge_u_, edge_v_, normal_;
    double area_;
    Rgb radiance_;
    bool two_sided_;
};

class EnvironmentLight : public Light {
public:
    explicit EnvironmentLight(const Rgb& radiance) : radiance_(radiance) {}

    bool sample_incident(const Vec3&, Rng& rng, LightSample& out) const override {
        const double u1 = rng.uniform(), u2 = rng.uniform();
        out.wi = sample_uniform_sphere(u1, u2);
        out.distance = kInfinity;
        out.weight = radiance_ * (4.0 * kPi);
        return true;
    }
    // Direction uniform over the sphere (pdf 1 / 4 pi), origin uniform over the silhouette of what
    // can be lit seen along it (pdf 1 / A_proj(dir)): power L 4 pi A_proj(dir), whose mean over
    // directions is power() = L pi S (emission_bounds.h).
    EmissionSample sample_emission(Rng& rng) const override {
        const double u1 = rng.uniform(), u2 = rng.uniform(), u3 = rng.uniform(), u4 = rng.uniform(),
                     u5 = rng.uniform();
        const Vec3 dir = sample_uniform_sphere(u1, u2);   // travel direction of the photon
        return {Ray{bounds_.sample_origin(dir, u3, u4, u5), dir}, radiance_ * (4.0 * kPi * bounds_.projected_area(dir))};
    }
    Rgb power() const override { return radiance_ * (4.0 * kPi * bounds_.mean_projected_area()); }
    Rgb escaped_radiance(const Vec3&) const override { return radiance_; }
    void set_scene_bounds(const Bounds3& b) override { bounds_.set(b); }
    std::string describe() const override { return "constant environment, radiance " + rgb_string(radiance_); }

private:
    Rgb radiance_;
    EmissionBounds bounds_;
};

}  // namespace

std::unique_ptr<Light> make_light(Params& p) {
    const std::string type = p.choice("type", {"point", "spot", "directional", "quad", "environment"});
    const Range non_negative = Range::at_least(0.0);
    std::unique_ptr<Light> light;
    if (type == "point") {
        const Vec3 position = p.vec3("position");
        light = std::make_unique<PointLight>(position, p.rgb("intensity", non_negative));
    } else if (type == "spot") {
        const Vec3 position = p.vec3("position");
        const Vec3 look_at = p.vec3("look_at");
        if ((look_at - position).norm() == 0.0) p.fail("look_at", "must differ from position");
        const Rgb intensity = p.rgb("intensity", non_negative);
        const double angle = p.real("cone_angle", 30.0, {0.0, 180.0, true, false});
        light = std::make_unique<SpotLight>(position, (look_at - position).normalized(), intensity,
                                            std::cos(angle * kPi / 180.0));
    } else if (type == "directional") {
        const Vec3 direction = p.vec3("direction");
        if (direction.norm() == 0.0) p.fail("direction", "must be a non-zero vector");
        light = std::make_unique<DirectionalLight>(direction.normalized(), p.rgb("irradiance", non_negative));
    } else if (type == "quad") {
        const Vec3 center = p.vec3("center");
        // Half edges, as for quad shapes: the corners are center +- u +- v.
        const Vec3 u = p.vec3("u");
        const Vec3 v = p.vec3("v");
        if (u.cross(v).norm() == 0.0) p.fail("v", "u and v must span a non-zero area");
        const Rgb radiance = p.rgb("radiance", non_negative);
        light = std::make_unique<QuadLight>(center, 2.0 * u, 2.0 * v, radiance, p.boolean("two_sided", false));
    } else {
        light = std::make_unique<EnvironmentLight>(p.rgb("radiance", non_negative));
    }
    p.finish();
    return light;
}

}  // namespace vpm
