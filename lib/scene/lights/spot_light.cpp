// type = "spot": position, look_at, intensity (W/sr), cone_angle (degrees, half-angle in (0, 180],
// default 30); constant intensity inside the cone, zero outside (no falloff ring: keeps the
// emitted power exact). Photons go toward what can be lit: when the cone around the scene's box
// (scene/lights/emission_cone.h) lies inside the spot's cone, photons are emitted in it alone; when the
// two do not meet, the light emits no photons (its power reaches nothing). Otherwise, where most of
// its cone reaches nothing, half of its photons follow a guide (scene/emission_guides.h).
#include <sstream>

#include <algorithm>

#include "core/sampling/sampling.h"
#include "scene/lights/emission_cone.h"
#include "scene/lights/guided_emission.h"
#include "scene/lights/light_registry.h"
#include "config/params.h"

namespace vpm {

namespace {

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
        auto own = [this](Rng& r) {
            const double u1 = r.uniform(), u2 = r.uniform();
            return own_direction(u1, u2);
        };
        if (!guided_.active()) return {Ray{position_, own(rng)}, power()};
        // One-sample mixture with the guide: I over the mixture's density where the spot shines, 0
        // outside its cone (a guide cell may straddle the cone's edge).
        const Vec3 dir = guided_.sample(rng, own);
        const double pdf = guided_.pdf(emission_direction_pdf(dir), dir);
        const bool lit = dir.dot(frame_.n) >= cos_max_;
        return {Ray{position_, dir}, lit && pdf > 0.0 ? Rgb(intensity_ / pdf) : Rgb::Zero()};
    }
    bool delta() const override { return true; }
    bool delta_position(Vec3& position) const override {
        position = position_;
        return true;
    }
    bool guide_origin(Vec3& origin, double& start) const override {
        if (emit_in_scene_cone_ || misses_scene_) return false;   // aimed at the scene's cone already, or dark
        origin = position_;
        start = 0.0;
        return true;
    }
    double emission_direction_pdf(const Vec3& w) const override {
        if (misses_scene_ || emit_in_scene_cone_) return 0.0;
        return w.dot(frame_.n) >= cos_max_ ? uniform_cone_pdf(cos_max_) : 0.0;
    }
    void set_emission_guide(std::shared_ptr<const DirectionGuide> guide, double share) override {
        guided_.set(std::move(guide), share);
    }
    // The power emitted toward what can be lit (see the file comment).
    Rgb power() const override {
        if (misses_scene_) return Rgb::Zero();
        return intensity_ * (emit_in_scene_cone_ ? scene_cone_.solid_angle() : 2.0 * kPi * (1.0 - cos_max_));
    }
    void set_scene_bounds(const Bounds3& b) override {
        scene_cone_ = EmissionCone::towards(position_, b);
        emit_in_scene_cone_ = misses_scene_ = false;
        if (scene_cone_.full_sphere) return;
        const double spot = std::acos(std::clamp(cos_max_, -1.0, 1.0));
        const double scene = std::acos(std::clamp(scene_cone_.cos_max, -1.0, 1.0));
        const double between = std::acos(std::clamp(frame_.n.dot(scene_cone_.frame.n), -1.0, 1.0));
        emit_in_scene_cone_ = between + scene <= spot;
        misses_scene_ = between >= spot + scene;
    }
    std::string describe() const override {
        std::ostringstream s;
        s << "spot light at (" << position_.transpose() << ") towards (" << frame_.n.transpose()
          << "), half-angle " << std::acos(cos_max_) * 180.0 / kPi << " deg, intensity " << format_rgb(intensity_);
        return s.str();
    }

private:
    Vec3 own_direction(double u1, double u2) const {
        return emit_in_scene_cone_ ? scene_cone_.sample(u1, u2) : frame_.to_world(sample_uniform_cone(u1, u2, cos_max_)).normalized();
    }

    Vec3 position_;
    Frame frame_;
    Rgb intensity_;
    double cos_max_;
    EmissionCone scene_cone_;
    bool emit_in_scene_cone_ = false;   // the scene's cone lies inside the spot's
    bool misses_scene_ = false;         // the two cones do not meet
    GuidedEmission guided_;   // inactive: the spot's own emission only
};

}  // namespace

std::unique_ptr<Light> make_spot_light(Params& p) {
    const Vec3 position = p.vec3("position");
    const Vec3 look_at = p.vec3("look_at");
    if ((look_at - position).norm() == 0.0) p.fail("look_at", "must differ from position");
    const Rgb intensity = p.rgb("intensity", emission_range());
    const double angle = p.real("cone_angle", 30.0, {0.0, 180.0, true, false});
    return std::make_unique<SpotLight>(position, (look_at - position).normalized(), intensity,
                                        std::cos(angle * kPi / 180.0));
}

}  // namespace vpm
