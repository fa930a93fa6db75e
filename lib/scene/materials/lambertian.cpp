// material = "lambertian": reflectance (number or [r,g,b] in [0,1], default 0.5). Ideal diffuse
// reflection f = reflectance / pi on the side the ray comes from, cosine-weighted sampling. The
// walks take this step themselves (transport/walk_steps.h diffuse_bounce) from diffuse_reflectance().
#include "core/sampling/sampling.h"
#include "scene/lights/light_registry.h"
#include "scene/materials/material.h"
#include "config/params.h"

namespace vpm {

namespace {

class Lambertian final : public Material {
public:
    explicit Lambertian(const Rgb& reflectance) : reflectance_(reflectance) {}
    std::string name() const override { return "lambertian"; }
    std::string describe() const override { return "lambertian, reflectance " + format_rgb(reflectance_); }
    Rgb diffuse_reflectance() const override { return reflectance_; }
    Rgb eval(const Vec3&, const Vec3& n, bool, const Vec3& dir, Transport) const override {
        return dir.dot(n) > 0.0 ? Rgb(reflectance_ * kInvPi) : Rgb::Zero();
    }
    double pdf(const Vec3&, const Vec3& n, bool, const Vec3& dir) const override {
        return std::max(0.0, dir.dot(n)) * kInvPi;
    }
    bool sample(const Vec3&, const Vec3& n, bool, Transport, double u1, double u2, double, MaterialSample& out) const override {
        out.dir = Frame(n).to_world(sample_cosine_hemisphere(u1, u2)).normalized();
        out.pdf = std::max(0.0, out.dir.dot(n)) * kInvPi;
        out.weight = reflectance_;
        out.delta = false;
        out.transmitted = false;
        return out.pdf > 0.0;
    }

private:
    Rgb reflectance_;
};

}  // namespace

std::shared_ptr<const Material> make_lambertian_material(Params& p) {
    return std::make_shared<Lambertian>(p.rgb("reflectance", Rgb::Constant(0.5), Range::closed(0, 1)));
}

}  // namespace vpm
