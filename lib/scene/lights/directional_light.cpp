// type = "directional": direction (travel direction), irradiance (W/m^2); parallel light. Photons
// start on the silhouette of the bounds of what can be lit (scene/lights/emission_bounds.h), and only the
// light crossing it is emitted.
#include <sstream>

#include "core/sampling/sampling.h"
#include "scene/lights/light_registry.h"
#include "config/params.h"
#include "scene/lights/emission_bounds.h"

namespace vpm {

namespace {

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
        const EmissionLine line = bounds_.sample_line(dir_, u1, u2, u3);
        return {Ray{line.origin, dir_}, irradiance_ * line.area};
    }
    // Only the light crossing the silhouette of what can be lit (emission_bounds.h).
    Rgb power() const override { return irradiance_ * bounds_.projected_area(dir_); }
    void set_scene_bounds(const Bounds3& b) override { bounds_.set(b); }
    bool at_infinity() const override { return true; }
    bool delta() const override { return true; }
    bool set_emission_focus(const Bounds3& f) override {
        bounds_.set_focus(f);
        return bounds_.focused();
    }
    std::string describe() const override {
        std::ostringstream s;
        s << "directional light along (" << dir_.transpose() << "), irradiance " << format_rgb(irradiance_);
        return s.str();
    }

private:
    Vec3 dir_;
    Rgb irradiance_;
    EmissionBounds bounds_;
};

}  // namespace

std::unique_ptr<Light> make_directional_light(Params& p) {
    const Vec3 direction = p.vec3("direction");
    if (direction.norm() == 0.0) p.fail("direction", "must be a non-zero vector");
    return std::make_unique<DirectionalLight>(direction.normalized(), p.rgb("irradiance", emission_range()));
}

}  // namespace vpm
