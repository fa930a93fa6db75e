// type = "point": position, intensity (W/sr, rgb); shines uniformly in all directions and emits
// photons only toward what can be lit: uniformly over the scene box's silhouette from outside it
// (scene/lights/box_silhouette.h), in the cone around the box's sphere where the box is too small
// a speck for that (scene/lights/emission_cone.h), over the whole sphere from inside the box; where
// most of those directions reach nothing, half of the photons follow a guide instead
// (scene/emission_guides.h).
#include <sstream>

#include "core/sampling/sampling.h"
#include "scene/lights/box_silhouette.h"
#include "scene/lights/emission_cone.h"
#include "scene/lights/guided_emission.h"
#include "scene/lights/light_registry.h"
#include "config/params.h"

namespace vpm {

namespace {

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
        auto own = [this](Rng& r) { return own_direction(r); };
        if (!guided_.active()) return {Ray{position_, own(rng)}, power()};
        // One-sample mixture with the guide: I over the mixture's density, I * solid angle on average.
        const Vec3 dir = guided_.sample(rng, own);
        const double pdf = guided_.pdf(emission_direction_pdf(dir), dir);
        return {Ray{position_, dir}, pdf > 0.0 ? Rgb(intensity_ / pdf) : Rgb::Zero()};
    }
    bool delta() const override { return true; }
    bool delta_position(Vec3& position) const override {
        position = position_;
        return true;
    }
    bool guide_origin(Vec3& origin, double& start) const override {
        if (!silhouette_.valid() && !cone_.full_sphere) return false;   // a narrow cone already: nothing to guide
        origin = position_;
        start = 0.0;
        return true;
    }
    double emission_direction_pdf(const Vec3& w) const override {
        if (silhouette_.valid()) {
            double t0 = 0.0, t1 = 0.0;
            return box_.intersect(Ray{position_, w}, kInfinity, t0, t1) ? 1.0 / silhouette_.solid_angle() : 0.0;
        }
        return cone_.contains(w) ? 1.0 / cone_.solid_angle() : 0.0;
    }
    void set_emission_guide(std::shared_ptr<const DirectionGuide> guide, double share) override {
        guided_.set(std::move(guide), share);
    }
    // The power that can reach the scene's box (all of it from inside the box).
    Rgb power() const override {
        return intensity_ * (silhouette_.valid() ? silhouette_.solid_angle() : cone_.solid_angle());
    }
    void set_scene_bounds(const Bounds3& b) override {
        box_ = b;
        silhouette_ = BoxSilhouette(position_, b);
        cone_ = EmissionCone::towards(position_, b);
    }
    std::string describe() const override {
        std::ostringstream s;
        s << "point light at (" << position_.transpose() << "), intensity " << format_rgb(intensity_);
        return s.str();
    }

private:
    // A direction of the light's own emission (the box's silhouette, or the cone / sphere around it).
    Vec3 own_direction(Rng& rng) const {
        if (silhouette_.valid()) {
            const double u_face = rng.uniform(), u1 = rng.uniform(), u2 = rng.uniform();
            return silhouette_.sample(u_face, u1, u2);
        }
        const double u1 = rng.uniform(), u2 = rng.uniform();
        return cone_.sample(u1, u2);
    }

    Vec3 position_;
    Rgb intensity_;
    Bounds3 box_;
    BoxSilhouette silhouette_{Vec3::Zero(), Bounds3{}};
    EmissionCone cone_;
    GuidedEmission guided_;   // inactive: the light's own emission only
};

}  // namespace

std::unique_ptr<Light> make_point_light(Params& p) {
    const Vec3 position = p.vec3("position");
    return std::make_unique<PointLight>(position, p.rgb("intensity", emission_range()));
}

}  // namespace vpm
