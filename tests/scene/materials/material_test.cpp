// Materials (scene/materials/): the exact Fresnel term against the angle form of Fresnel's
// equations, and for every registered material the checks the phase function has: sample() against
// eval() and pdf(), the pdf's normalisation, reciprocity, no energy created; the dielectric's event
// probabilities, Snell's law, total internal reflection and the radiance / power convention at
// refraction; and the config errors of the [[shapes]] material keys.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/error.h"
#include "core/sampling/rng.h"
#include "core/sampling/sampling.h"
#include "scene/materials/fresnel.h"
#include "scene/materials/material_registry.h"
#include "support/sample_statistics.h"

using namespace vpm;
using vpm::test::Sample;

namespace {

std::shared_ptr<const Material> material(const std::string& keys) {
    auto doc = parse_config(keys, "shape.toml", ".");
    toml::table resolved;
    Params p(doc, &resolved);
    auto m = make_material(p);
    p.finish();
    return m;
}

std::string config_error(const std::string& keys) {
    try {
        material(keys);
    } catch (const ConfigError& e) {
        return e.what();
    }
    return "(no ConfigError)";
}

Vec3 uniform_dir(Rng& rng) {
    const double z = 1.0 - 2.0 * rng.uniform(), phi = 2.0 * kPi * rng.uniform();
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    return Vec3(r * std::cos(phi), r * std::sin(phi), z);
}

// A direction of travel d meeting a surface whose normal n faces it (d . n < 0).
void incident(Rng& rng, Vec3& d, Vec3& n) {
    n = uniform_dir(rng);
    d = uniform_dir(rng);
    if (d.dot(n) > 0.0) d = -d;
}

}  // namespace

TEST(Fresnel, MatchesTheAngleFormOfFresnelsEquations) {
    // rs = -sin(i - t) / sin(i + t), rp = tan(i - t) / tan(i + t), n1 sin i = n2 sin t.
    for (double eta : {1.2, 1.5, 2.4, 1.0 / 1.5}) {
        for (double theta_i = 0.05; theta_i < kPi / 2; theta_i += 0.1) {
            const double sin_t = std::sin(theta_i) / eta;
            double cos_t = -1.0;
            const double f = fresnel_dielectric(std::cos(theta_i), eta, cos_t);
            if (sin_t >= 1.0) {
                EXPECT_EQ(f, 1.0) << "total internal reflection, eta " << eta << " theta " << theta_i;
                EXPECT_EQ(cos_t, 0.0);
                continue;
            }
            const double theta_t = std::asin(sin_t);
            const double rs = -std::sin(theta_i - theta_t) / std::sin(theta_i + theta_t);
            const double rp = std::tan(theta_i - theta_t) / std::tan(theta_i + theta_t);
            EXPECT_NEAR(f, 0.5 * (rs * rs + rp * rp), 1e-12) << "eta " << eta << " theta " << theta_i;
            EXPECT_NEAR(cos_t, std::cos(theta_t), 1e-12);
        }
    }
    EXPECT_NEAR(fresnel_dielectric(1.0, 1.5), 0.04, 1e-12);   // ((1.5 - 1) / (1.5 + 1))^2
    EXPECT_NEAR(fresnel_dielectric(0.0, 1.5), 1.0, 1e-12);    // grazing
}

TEST(Fresnel, IsTheSameFromBothSides) {
    // Reciprocity of the interface: the pair of directions (i, t) reflects the same share either way.
    for (double eta : {1.33, 1.5, 3.0})
        for (double cos_i = 0.01; cos_i <= 1.0; cos_i += 0.07) {
            double cos_t;
            const double f = fresnel_dielectric(cos_i, eta, cos_t);
            double cos_back;
            EXPECT_NEAR(fresnel_dielectric(cos_t, 1.0 / eta, cos_back), f, 1e-12);
            EXPECT_NEAR(cos_back, cos_i, 1e-12);
        }
}

TEST(Materials, EveryMaterialsSampleAgreesWithEvalAndPdfAndCreatesNoEnergy) {
    for (const std::string& name : material_names()) {
        const auto m = material("material = '" + name + "'");
        EXPECT_EQ(m->name(), name);
        Rng rng(7, 0);
        Rgb weight_sum = Rgb::Zero();
        double pdf_integral = 0.0;
        constexpr int kN = 200000;
        for (int i = 0; i < kN; ++i) {
            Vec3 d, n;
            incident(rng, d, n);
            const bool exiting = rng.uniform() < 0.5;
            // The pdf over the whole sphere by uniform sampling: 1 for smooth lobes, 0 for delta ones.
            pdf_integral += m->pdf(d, n, exiting, uniform_dir(rng)) * 4.0 * kPi;
            MaterialSample s;
            const double u1 = rng.uniform(), u2 = rng.uniform(), u3 = rng.uniform();
            if (!m->sample(d, n, exiting, Transport::power, u1, u2, u3, s)) continue;
            EXPECT_NEAR(s.dir.norm(), 1.0, 1e-12);
            weight_sum += s.weight;
            if (!s.delta) {
                ASSERT_GT(s.pdf, 0.0);
                EXPECT_NEAR(s.pdf, m->pdf(d, n, exiting, s.dir), 1e-12);
                const Rgb expect = m->eval(d, n, exiting, s.dir, Transport::power) * std::abs(s.dir.dot(n)) / s.pdf;
                EXPECT_TRUE(s.weight.isApprox(expect, 1e-12)) << name;
            } else {
                EXPECT_EQ(m->pdf(d, n, exiting, s.dir), 0.0) << name;
                EXPECT_TRUE((m->eval(d, n, exiting, s.dir, Transport::power) == 0.0).all()) << name;
            }
        }
        const Rgb mean = weight_sum / kN;
        EXPECT_TRUE((mean <= 1.0 + 1e-12).all()) << name << " creates energy: " << mean.transpose();
        if (m->specular() || (m->diffuse_reflectance() == 0.0).all()) {
            EXPECT_EQ(pdf_integral, 0.0) << name;
        } else {
            EXPECT_NEAR(pdf_integral / kN, 1.0, 0.02) << name;   // SE of the uniform estimate ~0.0045
        }
    }
}

TEST(Materials, LambertianIsReciprocalAndReflectsItsAlbedo) {
    const auto m = material("material = 'lambertian'\nreflectance = [0.2, 0.5, 0.9]");
    EXPECT_TRUE(m->diffuse_reflectance().isApprox(Rgb(0.2, 0.5, 0.9)));
    EXPECT_FALSE(m->specular());
    Rng rng(3, 1);
    for (int i = 0; i < 1000; ++i) {
        Vec3 d, n;
        incident(rng, d, n);
        Vec3 w = uniform_dir(rng);
        if (w.dot(n) < 0.0) w = -w;
        // f(d -> w) = f(-w -> -d): the reversed path meets the same side.
        EXPECT_TRUE(m->eval(d, n, false, w, Transport::radiance).isApprox(m->eval(-w, n, false, -d, Transport::radiance)));
        EXPECT_TRUE(m->eval(d, n, false, w, Transport::radiance).isApprox(Rgb(0.2, 0.5, 0.9) * kInvPi));
        EXPECT_TRUE((m->eval(d, n, false, -w, Transport::radiance) == 0.0).all());   // nothing through it
    }
}

TEST(Materials, BlackReflectsNothing) {
    const auto m = material("material = 'black'");
    MaterialSample s;
    EXPECT_FALSE(m->sample(Vec3(0, 0, -1), Vec3(0, 0, 1), false, Transport::power, 0.5, 0.5, 0.5, s));
    EXPECT_TRUE((m->diffuse_reflectance() == 0.0).all());
}

TEST(Materials, MirrorReflectsAboutTheNormalWithItsReflectance) {
    const auto m = material("material = 'mirror'\nreflectance = [0.9, 0.8, 0.7]");
    EXPECT_TRUE(m->specular());
    EXPECT_TRUE((m->diffuse_reflectance() == 0.0).all());
    Rng rng(5, 2);
    for (int i = 0; i < 1000; ++i) {
        Vec3 d, n;
        incident(rng, d, n);
        for (Transport mode : {Transport::radiance, Transport::power}) {
            MaterialSample s;
            ASSERT_TRUE(m->sample(d, n, false, mode, rng.uniform(), 0.5, 0.5, s));
            EXPECT_NEAR(s.dir.dot(n), -d.dot(n), 1e-12);                       // equal angles
            EXPECT_LT((s.dir - d - 2.0 * (-d.dot(n)) * n).norm(), 1e-12);     // in the plane of incidence
            EXPECT_TRUE(s.weight.isApprox(Rgb(0.9, 0.8, 0.7)));
            // Reciprocal: the reversed ray reflects back along -d.
            MaterialSample back;
            ASSERT_TRUE(m->sample(-s.dir, n, false, mode, 0.5, 0.5, 0.5, back));
            EXPECT_LT((back.dir + d).norm(), 1e-12);
        }
    }
}

TEST(Materials, DielectricReflectsWithTheFresnelProbabilityAndRefractsBySnell) {
    const double ior = 1.5;
    const auto m = material("material = 'dielectric'");   // ior 1.5 by default
    EXPECT_TRUE(m->specular());
    EXPECT_TRUE(m->needs_closed_shape());
    const Vec3 n(0, 0, 1);
    for (bool exiting : {false, true}) {
        const double eta = exiting ? 1.0 / ior : ior;
        for (double theta : {0.0, 0.4, 0.7, 1.2, 1.5}) {
            const Vec3 d(std::sin(theta), 0.0, -std::cos(theta));
            const double f = fresnel_dielectric(std::cos(theta), eta);
            Rng rng(11, uint64_t(theta * 100) + (exiting ? 1000 : 0));
            Sample reflected;
            constexpr int kN = 40000;
            for (int i = 0; i < kN; ++i) {
                MaterialSample s;
                ASSERT_TRUE(m->sample(d, n, exiting, Transport::radiance, rng.uniform(), 0.5, 0.5, s));
                EXPECT_TRUE(s.delta);
                reflected.add(s.transmitted ? 0.0 : 1.0);
                if (s.transmitted) {
                    EXPECT_NEAR(s.pdf, 1.0 - f, 1e-12);
                    EXPECT_LT(s.dir.dot(n), 0.0);   // on through the surface
                    // Snell: n1 sin i = n2 sin t, in the plane of incidence.
                    const double sin_t = std::sqrt(s.dir.x() * s.dir.x() + s.dir.y() * s.dir.y());
                    EXPECT_NEAR(std::sin(theta), eta * sin_t, 1e-12);
                    EXPECT_NEAR(s.dir.y(), 0.0, 1e-12);
                    // Radiance carries 1 / eta^2 across; the reversed ray, 1 / (1 / eta)^2 = eta^2 back.
                    EXPECT_TRUE(s.weight.isApprox(Rgb::Constant(1.0 / (eta * eta)), 1e-12));
                    MaterialSample back, power;
                    ASSERT_TRUE(m->sample(-s.dir, -n, !exiting, Transport::radiance, 0.999999, 0.5, 0.5, back));
                    ASSERT_TRUE(back.transmitted);
                    EXPECT_LT((back.dir + d).norm(), 1e-9);
                    EXPECT_NEAR(back.pdf, s.pdf, 1e-12);   // the same Fresnel share both ways
                    EXPECT_TRUE((s.weight * back.weight).isApprox(Rgb::Ones(), 1e-12));
                    ASSERT_TRUE(m->sample(d, n, exiting, Transport::power, 0.999999, 0.5, 0.5, power));
                    EXPECT_TRUE(power.weight.isApprox(Rgb::Ones()));   // photons: power is not scaled
                } else {
                    EXPECT_NEAR(s.pdf, f, 1e-12);
                    EXPECT_TRUE(s.weight.isApprox(Rgb::Ones()));
                    EXPECT_NEAR(s.dir.z(), std::cos(theta), 1e-12);
                }
            }
            if (f == 1.0) {
                EXPECT_EQ(reflected.mean(), 1.0) << "total internal reflection at theta " << theta;
            } else {
                EXPECT_NEAR(reflected.mean(), f, 4.0 * std::sqrt(f * (1.0 - f) / kN) + 1e-12) << theta << " exiting " << exiting;
            }
        }
    }
}

TEST(Materials, DielectricTotalInternalReflectionBeyondTheCriticalAngle) {
    const auto m = material("material = 'dielectric'\nior = 2.0");
    const double critical = std::asin(0.5);
    const Vec3 n(0, 0, 1);
    for (double theta : {critical + 1e-6, 1.0, 1.5}) {
        const Vec3 d(std::sin(theta), 0.0, -std::cos(theta));
        for (double u : {0.0, 0.5, 0.999999}) {
            MaterialSample s;
            ASSERT_TRUE(m->sample(d, n, true, Transport::power, u, 0.5, 0.5, s));
            EXPECT_FALSE(s.transmitted);
            EXPECT_EQ(s.pdf, 1.0);
        }
    }
    const Vec3 d(std::sin(critical - 0.01), 0.0, -std::cos(critical - 0.01));
    MaterialSample s;
    ASSERT_TRUE(m->sample(d, n, true, Transport::power, 0.999999, 0.5, 0.5, s));
    EXPECT_TRUE(s.transmitted);   // just inside the cone: refracts out
}

TEST(Materials, DielectricBothEventsAreSamplesTwoOutcomesWithTheirProbabilities) {
    // Camera paths that split at glass (render/photon_map/camera_path.h) take both events at once:
    // the reflection with pdf F and the refraction with pdf 1 - F, each as sample() gives it.
    const auto m = material("material = 'dielectric'\nior = 2.0\ntransmittance = [1, 0.5, 0.25]");
    const Vec3 n(0, 0, 1);
    for (bool exiting : {false, true}) {
        const double eta = exiting ? 0.5 : 2.0;
        for (double theta : {0.0, 0.4, 0.52, 1.2}) {
            const Vec3 d(std::sin(theta), 0.0, -std::cos(theta));
            const double f = fresnel_dielectric(std::cos(theta), eta);
            MaterialSample both[2], reflected, refracted;
            const bool two = m->both_events(d, n, exiting, Transport::radiance, both);
            EXPECT_EQ(two, f < 1.0) << theta << " exiting " << exiting;   // beyond the critical angle: reflection alone
            if (!two) continue;
            ASSERT_TRUE(m->sample(d, n, exiting, Transport::radiance, 0.0, 0.5, 0.5, reflected));
            ASSERT_TRUE(m->sample(d, n, exiting, Transport::radiance, 0.999999, 0.5, 0.5, refracted));
            EXPECT_FALSE(both[0].transmitted);
            EXPECT_TRUE(both[1].transmitted);
            EXPECT_NEAR(both[0].pdf, f, 1e-12);
            EXPECT_NEAR(both[0].pdf + both[1].pdf, 1.0, 1e-12);
            EXPECT_LT((both[0].dir - reflected.dir).norm(), 1e-12);
            EXPECT_LT((both[1].dir - refracted.dir).norm(), 1e-12);
            EXPECT_TRUE(both[1].weight.isApprox(refracted.weight, 1e-12));
            EXPECT_NEAR(both[1].radiance_scale, 1.0 / (eta * eta), 1e-12);
        }
    }
    MaterialSample out[2];
    EXPECT_FALSE(material("material = 'mirror'")->both_events(Vec3(0, 0.6, -0.8), n, false, Transport::radiance, out));
    EXPECT_FALSE(material("material = 'dielectric'\ntransmittance = 0")->both_events(Vec3(0, 0, -1), n, false,
                                                                                       Transport::radiance, out));
}

TEST(Materials, DielectricTransmittanceTintsEachCrossing) {
    const auto m = material("material = 'dielectric'\nior = 1.33\ntransmittance = [1, 0.5, 0.25]");
    MaterialSample s;
    ASSERT_TRUE(m->sample(Vec3(0, 0, -1), Vec3(0, 0, 1), false, Transport::power, 0.999, 0.5, 0.5, s));
    ASSERT_TRUE(s.transmitted);
    EXPECT_TRUE(s.weight.isApprox(Rgb(1, 0.5, 0.25)));
    ASSERT_TRUE(m->sample(Vec3(0, 0, -1), Vec3(0, 0, 1), false, Transport::radiance, 0.999, 0.5, 0.5, s));
    EXPECT_TRUE(s.weight.isApprox(Rgb(1, 0.5, 0.25) / (1.33 * 1.33)));
}

TEST(Materials, ConfigErrorsNameTheKeyAndTheAllowedValues) {
    EXPECT_NE(config_error("material = 'dielectric'\nior = 1.0").find("ior"), std::string::npos);
    EXPECT_NE(config_error("material = 'dielectric'\nior = 1.0").find("(1, 4]"), std::string::npos)
        << config_error("material = 'dielectric'\nior = 1.0");
    EXPECT_NE(config_error("material = 'dielectric'\nior = 4.5").find("ior"), std::string::npos);
    EXPECT_EQ(config_error("material = 'dielectric'\nior = 4.0"), "(no ConfigError)");
    EXPECT_NE(config_error("material = 'dielectric'\ntransmittance = 1.5").find("transmittance"), std::string::npos);
    EXPECT_NE(config_error("material = 'mirror'\nreflectance = -0.1").find("reflectance"), std::string::npos);
    const std::string wrong = config_error("material = 'mirror'\nior = 1.5");
    EXPECT_NE(wrong.find("ior"), std::string::npos) << wrong;
    EXPECT_NE(wrong.find("dielectric"), std::string::npos) << wrong;
    EXPECT_NE(wrong.find("reflectance"), std::string::npos) << wrong;   // what a mirror takes
    EXPECT_NE(config_error("material = 'black'\nreflectance = 0.5").find("reflectance"), std::string::npos);
    const std::string unknown = config_error("material = 'glass'");
    EXPECT_NE(unknown.find("dielectric"), std::string::npos) << unknown;   // the allowed names
    EXPECT_NE(unknown.find("mirror"), std::string::npos) << unknown;
    EXPECT_NE(config_error("material = 'dielectric'\nroughness = 0.1").find("roughness"), std::string::npos);
}
