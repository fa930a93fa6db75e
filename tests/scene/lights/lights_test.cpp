// Lights: next-event estimates of irradiance against closed forms, and emission consistent with power().
#include <gtest/gtest.h>

#include "core/error.h"
#include "scene/lights/light_registry.h"
#include "scene/scene.h"

#include "support/light_from_config.h"
#include "support/render_statistics.h"

using namespace vpm;

namespace {

using test::light_from;

// Monte Carlo irradiance at x on a surface with normal n, from NEE samples.
void irradiance(const Light& light, const Vec3& x, const Vec3& n, int samples, double& mean, double& se) {
    Rng rng(17, 3);
    double sum = 0.0, sum2 = 0.0;
    LightSample s;
    for (int i = 0; i < samples; ++i) {
        double e = 0.0;
        if (light.sample_incident(x, rng, s)) e = s.weight[0] * std::max(0.0, s.wi.dot(n));
        sum += e;
        sum2 += e * e;
    }
    mean = sum / samples;
    se = std::sqrt(std::max(0.0, sum2 / samples - mean * mean) / samples);
}

}  // namespace

TEST(Lights, PointLightInverseSquare) {
    auto light = light_from("[[lights]]\ntype='point'\nposition=[0,2,0]\nintensity=[3,3,3]\n");
    double mean, se;
    irradiance(*light, Vec3::Zero(), Vec3::UnitY(), 10, mean, se);
    EXPECT_NEAR(mean, 3.0 / 4.0, 1e-12);
    EXPECT_NEAR(light->power()[0], 3.0 * 4.0 * kPi, 1e-9);
}

TEST(Lights, QuadLightIrradianceOnAxis) {
    // Square of half-edge a at height h, facing down; receiver on the axis facing up.
    const double a = 0.5, h = 1.3, L = 2.0;
    auto light = light_from("[[lights]]\ntype='quad'\ncenter=[0,1.3,0]\nu=[0.5,0,0]\nv=[0,0,0.5]\nradiance=2\n");
    double mean, se;
    irradiance(*light, Vec3::Zero(), Vec3::UnitY(), 400000, mean, se);
    const double X = a / h, s = std::sqrt(1.0 + X * X);
    const double expected = 4.0 * (L / 2.0) * 2.0 * (X / s) * std::atan(X / s);   // four corner rectangles
    EXPECT_NEAR(mean, expected, 3.0 * se);
    EXPECT_NEAR(light->power()[0], L * kPi * 1.0, 1e-12);   // area (2a)^2 = 1
    // One-sided: nothing above it.
    Rng rng(1, 1);
    LightSample ls;
    EXPECT_FALSE(light->sample_incident(Vec3(0, 3, 0), rng, ls));
}

TEST(Lights, EnvironmentIrradianceIsPiL) {
    auto light = light_from("[[lights]]\ntype='environment'\nradiance=0.7\n");
    double mean, se;
    irradiance(*light, Vec3::Zero(), Vec3(0.3, 0.4, 0.5).normalized(), 400000, mean, se);
    EXPECT_NEAR(mean, kPi * 0.7, 3.0 * se);
    EXPECT_DOUBLE_EQ(light->escaped_radiance(Vec3::UnitX())[2], 0.7);
}

TEST(Lights, SpotLightConeAndPower) {
    auto light = light_from("[[lights]]\ntype='spot'\nposition=[0,1,0]\nlook_at=[0,0,0]\nintensity=5\ncone_angle=30\n");
    Rng rng(1, 1);
    LightSample ls;
    EXPECT_TRUE(light->sample_incident(Vec3(0.5, 0, 0), rng, ls));    // 26.6 deg off axis
    EXPECT_FALSE(light->sample_incident(Vec3(0.7, 0, 0), rng, ls));   // 35 deg off axis
    EXPECT_NEAR(light->power()[0], 5.0 * 2.0 * kPi * (1.0 - std::cos(kPi / 6.0)), 1e-12);
    for (int i = 0; i < 1000; ++i) {
        const EmissionSample e = light->sample_emission(rng);
        ASSERT_GE(e.ray.dir.dot(-Vec3::UnitY()), std::cos(kPi / 6.0) - 1e-12);
    }
}

TEST(Lights, EmissionOfLightsAtInfinityCoversWhatCanBeLitAndNothingElse) {
    // Photons of lights at infinity start just outside the box of what can be lit and every one
    // of them enters it (none is emitted where it can reach nothing); the mean photon power is the
    // light's power: irradiance x the box's projected area (directional), L pi S (environment:
    // mean projected area S / 4 over directions, Cauchy's formula), checked by Monte Carlo.
    Bounds3 b{Vec3(-1, -2, -1), Vec3(3, 1, 2)};   // extents 4, 3, 3: faces 9, 12, 12, S = 66
    const Vec3 d = Vec3(1, -2, 0.5).normalized();
    const double a_proj = std::abs(d[0]) * 9.0 + std::abs(d[1]) * 12.0 + std::abs(d[2]) * 12.0;
    for (const char* text : {"[[lights]]\ntype='directional'\ndirection=[1,-2,0.5]\nirradiance=1.5\n",
                             "[[lights]]\ntype='environment'\nradiance=0.2\n"}) {
        const bool directional = std::string(text).find("directional") != std::string::npos;
        auto light = light_from(text);
        light->set_scene_bounds(b);
        const double expected = directional ? 1.5 * a_proj : 0.2 * kPi * 66.0;
        EXPECT_NEAR(light->power()[0], expected, 1e-12 * expected);
        Rng rng(2, 2);
        test::Sample power;
        for (int i = 0; i < 20000; ++i) {
            const EmissionSample e = light->sample_emission(rng);
            ASSERT_FALSE(b.contains(e.ray.origin));
            double t0, t1;
            ASSERT_TRUE(b.intersect(e.ray, kInfinity, t0, t1)) << "a photon that misses what can be lit";
            if (directional) {
                ASSERT_NEAR(e.power[0], light->power()[0], 1e-9 * light->power()[0]);
            }
            power.add(e.power[0]);
        }
        EXPECT_NEAR(power.mean(), expected, 3.0 * power.se() + 1e-9 * expected);
    }
}

TEST(Lights, ConfigErrors) {
    EXPECT_THROW(light_from("[[lights]]\ntype='quad'\ncenter=[0,0,0]\nu=[1,0,0]\nv=[2,0,0]\nradiance=1\n"), ConfigError);
    EXPECT_THROW(light_from("[[lights]]\ntype='point'\nposition=[0,0,0]\nintensity=-1\n"), ConfigError);
    EXPECT_THROW(light_from("[[lights]]\ntype='spot'\nposition=[0,0,0]\nlook_at=[0,1,0]\nintensity=1\ncone_angle=0\n"), ConfigError);
    try {
        light_from("[[lights]]\ntype='point'\nposition=[0,0,0]\nintensity=1\ncolour=2\n");
        FAIL();
    } catch (const ConfigError& e) {
        EXPECT_NE(std::string(e.what()).find("light.toml:5: lights.0.colour: unknown key"), std::string::npos) << e.what();
    }
}

namespace {
// The message of the ConfigError that building `text`'s scene throws ("" when it builds).
std::string scene_error(const std::string& text) {
    try {
        auto doc = parse_config(text, "light.toml", ".");
        toml::table resolved;
        Params root(doc, &resolved);
        Scene::build(root, 4, 4);
    } catch (const ConfigError& e) {
        return e.what();
    }
    return "";
}
}  // namespace

// Issue 24: values whose power or sampling pdf is not a finite double, or whose radiance cannot
// reach a float32 image, are refused before any work, naming the key (they gave NaN/Inf images, a
// sphere light of radius 1e300 vanished from the path tracer and stopped the photon pass).
TEST(Lights, UnrepresentablePowerOrPdfIsRefusedNamingTheKey) {
    const std::string medium = "[[media]]\ntype='homogeneous'\nshape='sphere'\nradius=1\n";
    const std::pair<std::string, std::string> cases[] = {
        {"type='sphere'\ncenter=[0,2,0]\nradius=1e300\nradiance=5", "lights.0.radius"},
        {"type='sphere'\ncenter=[0,2,0]\nradius=1e-160\nradiance=5", "lights.0.radius"},
        {"type='sphere'\ncenter=[0,2,0]\nradius=1e153\nradiance=1e30", "lights.0.radius"},   // power overflows
        {"type='quad'\ncenter=[0,2,0]\nu=[1e200,0,0]\nv=[0,0,1]\nradiance=5", "lights.0.u"},
        {"type='quad'\ncenter=[0,2,0]\nu=[1e-155,0,0]\nv=[0,0,1e-155]\nradiance=5", "lights.0.v"},   // area underflows
        {"type='point'\nposition=[0,2,0]\nintensity=1e300", "lights.0.intensity"},
        {"type='spot'\nposition=[0,2,0]\nlook_at=[0,0,0]\nintensity=1e308", "lights.0.intensity"},
        {"type='directional'\ndirection=[0,-1,0]\nirradiance=[1,1e300,1]", "lights.0.irradiance"},
        {"type='environment'\nradiance=1e300", "lights.0.radiance"},
        {"type='quad'\ncenter=[0,2,0]\nu=[1,0,0]\nv=[0,0,1]\nradiance=1e308", "lights.0.radiance"},
    };
    for (const auto& [light, key] : cases) {
        const std::string msg = scene_error("[[lights]]\n" + light + "\n" + medium);
        EXPECT_NE(msg.find(key), std::string::npos) << light << " -> " << msg;
    }
    // Lights at infinity over huge bounds: the power is checked once the bounds are known.
    const std::string huge = "[[media]]\ntype='homogeneous'\nshape='sphere'\nradius=1e160\n";
    EXPECT_NE(scene_error("[[lights]]\ntype='environment'\nradiance=1\n" + huge).find("lights.0.radiance"), std::string::npos);
    // The largest allowed values build.
    EXPECT_EQ(scene_error("[[lights]]\ntype='point'\nposition=[0,2,0]\nintensity=1e30\n" + medium), "");
    EXPECT_EQ(scene_error("[[lights]]\ntype='sphere'\ncenter=[0,2,0]\nradius=1e100\nradiance=1e30\n" + medium), "");
}

TEST(Lights, PointAndSpotEmitOnlyTowardTheScene) {
    // A point light 10 units from a unit box: photons go over the box's silhouette (inside the cone
    // around the box's sphere), each with power I * its solid angle (the power that can arrive there).
    Bounds3 box;
    box.extend(Vec3(-0.5, -0.5, -0.5));
    box.extend(Vec3(0.5, 0.5, 0.5));
    const double radius = 0.5 * std::sqrt(3.0) * 1.001;
    auto point = light_from("[[lights]]\ntype='point'\nposition=[10,0,0]\nintensity=2\n");
    point->set_scene_bounds(box);
    const double s = radius / 10.0, solid = 2.0 * kPi * (1.0 - std::sqrt(1.0 - s * s));
    // Face-on from 10 units: 4 asin(a^2 / (a^2 + d^2)) with a = 0.5, d = 9.5.
    const double face = 4.0 * std::asin(0.25 / (0.25 + 9.5 * 9.5));
    EXPECT_NEAR(point->power()[0], 2.0 * face, 1e-9 * face);
    Rng rng(3, 1);
    int inside_cone = 0;
    const int n = 20000;
    for (int i = 0; i < n; ++i) {
        const EmissionSample e = point->sample_emission(rng);
        const Vec3 to_centre = -e.ray.origin;
        const double miss = (to_centre - to_centre.dot(e.ray.dir) * e.ray.dir).norm();   // distance of the line to the centre
        inside_cone += miss <= radius * (1.0 + 1e-9);
        EXPECT_DOUBLE_EQ(e.power[0], point->power()[0]);
    }
    EXPECT_EQ(inside_cone, n);
    // From inside the box the whole sphere is kept.
    auto inner = light_from("[[lights]]\ntype='point'\nposition=[0.1,0,0]\nintensity=2\n");
    inner->set_scene_bounds(box);
    EXPECT_NEAR(inner->power()[0], 8.0 * kPi, 1e-12);
    // A spot whose cone holds the scene's cone emits in the scene's cone; one looking away emits nothing.
    auto spot = light_from("[[lights]]\ntype='spot'\nposition=[10,0,0]\nlook_at=[0,0,0]\nintensity=2\ncone_angle=30\n");
    spot->set_scene_bounds(box);
    EXPECT_NEAR(spot->power()[0], 2.0 * solid, 1e-6 * 2.0 * solid);
    auto away = light_from("[[lights]]\ntype='spot'\nposition=[10,0,0]\nlook_at=[20,0,0]\nintensity=2\ncone_angle=30\n");
    away->set_scene_bounds(box);
    EXPECT_EQ(away->power()[0], 0.0);
    // A spot narrower than the scene's cone keeps its own cone.
    auto narrow = light_from("[[lights]]\ntype='spot'\nposition=[10,0,0]\nlook_at=[0,0,0]\nintensity=2\ncone_angle=1\n");
    narrow->set_scene_bounds(box);
    EXPECT_NEAR(narrow->power()[0], 2.0 * 2.0 * kPi * (1.0 - std::cos(kPi / 180.0)), 1e-12);
}
