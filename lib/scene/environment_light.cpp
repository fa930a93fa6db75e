// type = "environment": radiance; constant radiance from every direction, seen by rays that
// escape. Photons start on a disc covering the scene (scene/scene_disc.h).
#include <sstream>

#include "core/sampling.h"
#include "scene/light_registry.h"
#include "scene/params.h"
#include "scene/scene_disc.h"

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
        return true;
    }
    EmissionSample sample_emission(Rng& rng) const override {
        const double u1 = rng.uniform(), u2 = rng.uniform(), u3 = rng.uniform(), u4 = rng.uniform();
        const Vec3 dir = sample_uniform_sphere(u1, u2);   // travel direction of the photon
        return {Ray{disc_.sample_origin(dir, u3, u4), dir}, power()};
    }
    Rgb power() const override { return radiance_ * (4.0 * kPi * disc_.area()); }
    Rgb escaped_radiance(const Vec3&) const override { return radiance_; }
    void set_scene_bounds(const Bounds3& b) override { disc_.set(b); }
    std::string describe() const override { return "constant environment, radiance " + format_rgb(radiance_); }

private:
    Rgb radiance_;
    SceneDisc disc_;
};

}  // namespace

std::unique_ptr<Light> make_environment_light(Params& p) {
    const Range non_negative = Range::at_least(0.0);
    return std::make_unique<EnvironmentLight>(p.rgb("radiance", non_negative));
}

}  // namespace vpm
