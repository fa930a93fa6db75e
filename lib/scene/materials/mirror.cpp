// material = "mirror": reflectance ([r,g,b] in [0,1], default 1). A perfect specular reflector on
// both sides of the surface: the ray leaves along d reflected about the normal, its radiance or
// power times reflectance (the same factor for both: reflection keeps the solid angle).
#include "scene/lights/light_registry.h"
#include "scene/materials/fresnel.h"
#include "scene/materials/material.h"
#include "config/params.h"

namespace vpm {

namespace {

class Mirror final : public Material {
public:
    explicit Mirror(const Rgb& reflectance) : reflectance_(reflectance) {}
    std::string name() const override { return "mirror"; }
    std::string describe() const override { return "mirror, reflectance " + format_rgb(reflectance_); }
    bool specular() const override { return true; }
    Rgb eval(const Vec3&, const Vec3&, bool, const Vec3&, Transport) const override { return Rgb::Zero(); }
    double pdf(const Vec3&, const Vec3&, bool, const Vec3&) const override { return 0.0; }
    bool sample(const Vec3& d, const Vec3& n, bool, Transport, double, double, double, MaterialSample& out) const override {
        if ((reflectance_ == 0.0).all()) return false;
        out.dir = reflect(d, n).normalized();
        out.weight = reflectance_;
        out.pdf = 1.0;
        out.delta = true;
        out.transmitted = false;
        return true;
    }

private:
    Rgb reflectance_;
};

}  // namespace

std::shared_ptr<const Material> make_mirror_material(Params& p) {
    return std::make_shared<Mirror>(p.rgb("reflectance", Rgb::Ones(), Range::closed(0, 1)));
}

}  // namespace vpm
