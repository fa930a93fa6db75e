// material = "dielectric": ior (in (1, 4], default 1.5), transmittance ([r,g,b] in [0,1], default 1).
// Smooth glass in air: a ray meeting it is reflected with the exact Fresnel probability F (the
// mean of the s and p reflectances, fresnel.h) and refracted by Snell's law otherwise; beyond the
// critical angle inside, F = 1 (total internal reflection). Sampling the event with probability F
// makes a reflection weigh 1 and a refraction weigh `transmittance` (a tint per crossing, so a
// sphere's two crossings give it squared), times 1 / eta^2 for radiance (eta: index entered over
// index left; camera paths entering glass carry 1 / 2.25 at ior 1.5, leaving it 2.25) and times 1
// for photons, which carry power (material.h).
//
// The shape must be closed and consistently oriented (box, sphere, or a mesh whose every edge
// joins two triangles of opposite winding): which side is glass is read from its orientation.
// Media continue inside glass unchanged (docs/caustics.md).
#include <cmath>
#include <sstream>

#include "scene/lights/light_registry.h"
#include "scene/materials/fresnel.h"
#include "scene/materials/material.h"
#include "config/params.h"

namespace vpm {

namespace {

class Dielectric final : public Material {
public:
    Dielectric(double ior, const Rgb& transmittance) : ior_(ior), transmittance_(transmittance) {}
    std::string name() const override { return "dielectric"; }
    std::string describe() const override {
        std::ostringstream s;
        s << "dielectric, ior " << ior_ << ", transmittance " << format_rgb(transmittance_);
        return s.str();
    }
    bool specular() const override { return true; }
    bool needs_closed_shape() const override { return true; }
    Rgb eval(const Vec3&, const Vec3&, bool, const Vec3&, Transport) const override { return Rgb::Zero(); }
    double pdf(const Vec3&, const Vec3&, bool, const Vec3&) const override { return 0.0; }
    bool sample(const Vec3& d, const Vec3& n, bool exiting, Transport mode, double u1, double, double,
                MaterialSample& out) const override {
        const double eta = exiting ? 1.0 / ior_ : ior_;
        double cos_t = 0.0;
        const double f = fresnel_dielectric(-d.dot(n), eta, cos_t);
        out.delta = true;
        if (u1 < f) {
            out.dir = reflect(d, n).normalized();
            out.weight = Rgb::Ones();
            out.pdf = f;
            out.transmitted = false;
            return true;
        }
        out.dir = refract(d, n, eta, cos_t);
        out.radiance_scale = mode == Transport::radiance ? 1.0 / (eta * eta) : 1.0;
        out.weight = transmittance_ * out.radiance_scale;
        out.pdf = 1.0 - f;
        out.transmitted = true;
        return (out.weight > 0.0).any();
    }
    bool both_events(const Vec3& d, const Vec3& n, bool exiting, Transport mode, MaterialSample out[2]) const override {
        // sample() reflects for u1 < F: u1 = 0 takes the reflection, the largest u1 below 1 the refraction.
        return sample(d, n, exiting, mode, 0.0, 0.0, 0.0, out[0]) && !out[0].transmitted &&
               sample(d, n, exiting, mode, std::nextafter(1.0, 0.0), 0.0, 0.0, out[1]) && out[1].transmitted;
    }

private:
    double ior_;
    Rgb transmittance_;
};

}  // namespace

std::shared_ptr<const Material> make_dielectric_material(Params& p) {
    const double ior = p.real("ior", 1.5, Range{1.0, 4.0, true, false});
    const Rgb transmittance = p.rgb("transmittance", Rgb::Ones(), Range::closed(0, 1));
    return std::make_shared<Dielectric>(ior, transmittance);
}

}  // namespace vpm
