// type = "point": position, intensity (W/sr, rgb); shines uniformly in all directions and emits
// photons only toward what can be lit: uniformly over the scene box's silhouette from outside it
// (scene/lights/box_silhouette.h), in the cone around the box's sphere where the box is too small
// a speck for that (scene/lights/emission_cone.h), over the whole sphere from inside the box.
#include <sstream>

#include "core/sampling.h"
#include "scene/lights/box_silhouette.h"
#include "scene/lights/emission_cone.h"
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
        if (silhouette_.valid()) {
            const double u_face = rng.uniform(), u1 = rng.uniform(), u2 = rng.uniform();
            return {Ray{position_, silhouette_.sample(u_face, u1, u2)}, power()};
        }
        const double u1 = rng.uniform(), u2 = rng.uniform();
        return {Ray{position_, cone_.sample(u1, u2)}, power()};
    }
    // The power that can reach the scene's box (all of it from inside the box).
    Rgb power() const override {
        return intensity_ * (silhouette_.valid() ? silhouette_.solid_angle() : cone_.solid_angle());
    }
    void set_scene_bounds(const Bounds3& b) override {
        silhouette_ = BoxSilhouette(position_, b);
        cone_ = EmissionCone::towards(position_, b);
    }
    std::string describe() const override {
        std::ostringstream s;
        s << "point light at (" << position_.transpose() << "), intensity " << format_rgb(intensity_);
        return s.str();
    }

private:
    Vec3 position_;
    Rgb intensity_;
    BoxSilhouette silhouette_{Vec3::Zero(), Bounds3{}};
    EmissionCone cone_;
};

}  // namespace

std::unique_ptr<Light> make_point_light(Params& p) {
    const Vec3 position = p.vec3("position");
    return std::make_unique<PointLight>(position, p.rgb("intensity", emission_range()));
}

}  // namespace vpm
