// type = "environment": radiance; constant radiance from every direction, seen by rays that
// escape. Photons start on the silhouette of the bounds of what can be lit (scene/emission_bounds.h).
#include <sstream>

#include "core/sampling.h"
#include "scene/light_registry.h"
#include "scene/params.h"
#include "scene/emission_bounds.h"

namespace vpm {

namespace {

class EnvironmentLight : public Light {
public:
    explicit EnvironmentLight(const Rgb& radiance) : radiance_(radiance) {}

    bool sample_incident(const Vec3&, Rng& rng, LightSample& out) const override {
        const double u1 = rng.uniform(), u2 = rng.uniform();
        out.wi = sample_uniform_sphere(u1, u2);
        out.distance = kInfinity;
        out.weight = radiance_ * (4.0 * kPi);
        out.pdf = 1.0 / (4.0 * kPi);
        return true;
    }
    double pdf_incident(const Vec3&, const Vec3&) const override { return 1.0 / (4.0 * kPi); }
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
    std::string describe() const override { return "constant environment, radiance " + format_rgb(radiance_); }

private:
    Rgb radiance_;
    EmissionBounds bounds_;
};

}  // namespace

std::unique_ptr<Light> make_environment_light(Params& p) {
    const Range non_negative = Range::at_least(0.0);
    return std::make_unique<EnvironmentLight>(p.rgb("radiance", non_negative));
}

}  // namespace vpm
