// material = "black": no keys. Reflects nothing: a walk ends on it and a photon is absorbed.
#include "scene/materials/material.h"
#include "config/params.h"

namespace vpm {

namespace {

class Black final : public Material {
public:
    std::string name() const override { return "black"; }
    std::string describe() const override { return "black"; }
    Rgb eval(const Vec3&, const Vec3&, bool, const Vec3&, Transport) const override { return Rgb::Zero(); }
    double pdf(const Vec3&, const Vec3&, bool, const Vec3&) const override { return 0.0; }
    bool sample(const Vec3&, const Vec3&, bool, Transport, double, double, double, MaterialSample&) const override { return false; }
};

}  // namespace

std::shared_ptr<const Material> make_black_material(Params&) { return std::make_shared<Black>(); }

}  // namespace vpm
