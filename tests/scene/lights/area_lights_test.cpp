// Area lights (quad, sphere) as emitting geometry: their solid-angle pdfs (pdf_incident against
// the pdf reported by sample_incident, and normalised over directions), ray intersection and the
// radiance a ray sees, occlusion of shadow rays, sphere-light irradiance and emission.
#include <gtest/gtest.h>

#include "core/error.h"
#include "core/sampling/sampling.h"
#include "render/run/run_config.h"
#include "scene/lights/light_registry.h"

#include "support/light_from_config.h"
#include "support/sample_statistics.h"

using namespace vpm;

namespace {

using test::light_from;

const char* kSphere = "[[lights]]\ntype='sphere'\ncenter=[0.5,2,-1]\nradius=0.7\nradiance=[3,2,1]\n";
const char* kQuad = "[[lights]]\ntype='quad'\ncenter=[0,1.3,0]\nu=[0.5,0,0.1]\nv=[0,0,0.4]\nradiance=2\n";

}  // namespace

TEST(AreaLights, QuadPdfIncidentMatchesTheSamplePdf) {
    auto light = light_from(kQuad);
    Rng rng(5, 1);
    LightSample ls;
    int checked = 0;
    for (int i = 0; i < 2000; ++i) {
        const Vec3 x(4.0 * rng.uniform() - 2.0, 1.3 - 3.0 * rng.uniform(), 4.0 * rng.uniform() - 2.0);
        if (!light->sample_incident(x, rng, ls)) continue;
        ++checked;
        ASSERT_GT(ls.pdf, 0.0);
        EXPECT_NEAR(light->pdf_incident(x, ls.wi), ls.pdf, 1e-9 * ls.pdf);
        EXPECT_NEAR(ls.weight[0] * ls.pdf, 2.0, 1e-9);   // weight = L / pdf
        // The sampled point is on the light: a ray towards it meets it at that distance.
        EmitterHit h;
        ASSERT_TRUE(light->intersect(Ray{x, ls.wi}, kInfinity, h));
        EXPECT_NEAR(h.t, ls.distance, 1e-9 * ls.distance);
        EXPECT_EQ(h.radiance[0], 2.0);
    }
    EXPECT_GT(checked, 1000);
    // Behind a one-sided quad: no sample, pdf 0, and the ray sees its black back.
    const Vec3 above(0.1, 2.5, 0.05);
    EXPECT_FALSE(light->sample_incident(above, rng, ls));
    EXPECT_EQ(light->pdf_incident(above, -Vec3::UnitY()), 0.0);
    EmitterHit h;
    ASSERT_TRUE(light->intersect(Ray{above, -Vec3::UnitY()}, kInfinity, h));
    EXPECT_EQ(h.radiance.maxCoeff(), 0.0);
    EXPECT_NEAR(h.t, 1.2, 1e-12);
    // Directions that miss it have pdf 0.
    EXPECT_EQ(light->pdf_incident(Vec3::Zero(), Vec3::UnitX()), 0.0);
}

TEST(AreaLights, QuadPdfIntegratesToOne) {
    // E over uniform directions of pdf * 4 pi = integral of the pdf = 1 (within 4 standard errors).
    auto light = light_from(kQuad);
    Rng rng(6, 1);
    test::Sample s;
    for (int i = 0; i < 400000; ++i) s.add(light->pdf_incident(Vec3(0.2, 0.6, 0.1), sample_uniform_sphere(rng.uniform(), rng.uniform())) * 4.0 * kPi);
    EXPECT_NEAR(s.mean(), 1.0, 4.0 * s.se());
}

TEST(AreaLights, SpherePdfIntegratesToOneAndMatchesItsSamples) {
    auto light = light_from(kSphere);
    const Vec3 center(0.5, 2, -1);
    for (const Vec3& x : {Vec3(0, 0, 0), Vec3(0.5, 2, -1.75), Vec3(30, -20, 10)}) {
        // The integral of pdf_incident over all directions, by importance sampling a cone twice as
        // wide as the sphere's (so a far, small sphere is hit often): E[pdf / q] = 1.
        const double d = (center - x).norm(), sin_max = 0.7 / d;
        const double cone_cos = std::cos(std::min(kPi, 2.0 * std::asin(sin_max)));
        const Frame frame((center - x) / d);
        Rng rng(7, 1);
        test::Sample s;
        for (int i = 0; i < 200000; ++i) {
            const Vec3 w = frame.to_world(sample_uniform_cone(rng.uniform(), rng.uniform(), cone_cos)).normalized();
            s.add(light->pdf_incident(x, w) / uniform_cone_pdf(cone_cos));
        }
        EXPECT_NEAR(s.mean(), 1.0, 4.0 * s.se()) << "x = " << x.transpose();
        EXPECT_GT(s.se(), 0.0);
        // Every sample: its pdf is pdf_incident's, its point is on the sphere's near side and lit.
        LightSample ls;
        for (int i = 0; i < 2000; ++i) {
            ASSERT_TRUE(light->sample_incident(x, rng, ls));
            EXPECT_NEAR(light->pdf_incident(x, ls.wi), ls.pdf, 1e-9 * ls.pdf);
            EXPECT_NEAR((x + ls.distance * ls.wi - center).norm(), 0.7, 1e-9 * d);
            EXPECT_NEAR(ls.weight[1] * ls.pdf, 2.0, 1e-9);
            EmitterHit h;
            ASSERT_TRUE(light->intersect(Ray{x, ls.wi}, kInfinity, h));
            EXPECT_NEAR(h.t, ls.distance, 1e-7 * d);
            EXPECT_EQ(h.radiance[0], 3.0);
        }
    }
    // Inside the sphere nothing is lit (it emits outwards) and its inside looks black.
    LightSample ls;
    Rng rng(8, 1);
    EXPECT_FALSE(light->sample_incident(center + Vec3(0.1, 0, 0), rng, ls));
    EXPECT_EQ(light->pdf_incident(center, Vec3::UnitX()), 0.0);
    EmitterHit h;
    ASSERT_TRUE(light->intersect(Ray{center, Vec3::UnitX()}, kInfinity, h));
    EXPECT_NEAR(h.t, 0.7, 1e-12);
    EXPECT_EQ(h.radiance.maxCoeff(), 0.0);
}

TEST(AreaLights, SphereIrradianceAndEmission) {
    // Facing the sphere's centre at distance d: E = pi L (r / d)^2 (a Lambertian sphere looks like
    // a disc of its radiance filling the cone).
    auto light = light_from(kSphere);
    const Vec3 center(0.5, 2, -1), x(0.1, -0.4, 0.3);
    const Vec3 n = (center - x).normalized();
    Rng rng(9, 1);
    test::Sample e;
    LightSample ls;
    for (int i = 0; i < 200000; ++i)
        e.add(light->sample_incident(x, rng, ls) ? ls.weight[0] * std::max(0.0, ls.wi.dot(n)) : 0.0);
    const double d2 = (center - x).squaredNorm();
    EXPECT_NEAR(e.mean(), kPi * 3.0 * 0.49 / d2, 4.0 * e.se());
    // Power pi A L; photons leave the surface outwards with that power each.
    const double power = kPi * 4.0 * kPi * 0.49 * 3.0;
    EXPECT_NEAR(light->power()[0], power, 1e-12 * power);
    test::Sample cos_out;
    for (int i = 0; i < 20000; ++i) {
        const EmissionSample s = light->sample_emission(rng);
        const Vec3 normal = (s.ray.origin - center) / 0.7;
        ASSERT_NEAR(normal.norm(), 1.0, 1e-12);
        ASSERT_GT(s.ray.dir.dot(normal), 0.0);
        EXPECT_EQ(s.power[0], light->power()[0]);
        EmitterHit h;
        EXPECT_FALSE(light->intersect(s.ray, kInfinity, h)) << "a photon meeting its own light";
        cos_out.add(s.ray.dir.dot(normal));
    }
    EXPECT_NEAR(cos_out.mean(), 2.0 / 3.0, 4.0 * cos_out.se());   // cosine-distributed: E[cos] = 2/3
}

TEST(AreaLights, QuadPhotonsDoNotMeetTheirLight) {
    auto light = light_from("[[lights]]\ntype='quad'\ncenter=[3,1e3,-2]\nu=[0.5,0,0.1]\nv=[0,0,0.4]\nradiance=2\ntwo_sided=true\n");
    Rng rng(10, 1);
    for (int i = 0; i < 20000; ++i) {
        EmitterHit h;
        EXPECT_FALSE(light->intersect(light->sample_emission(rng).ray, kInfinity, h));
    }
}

TEST(AreaLights, LightsAreOpaqueExceptToTheirOwnShadowRays) {
    const std::string text = R"(
[camera]
position = [0, 0, 5]
look_at = [0, 0, 0]
[[lights]]
type = "quad"
center = [0, 1, 0]
u = [0.5, 0, 0]
v = [0, 0, 0.5]
radiance = 1
two_sided = true
[[lights]]
type = "sphere"
center = [0, 3, 0]
radius = 0.5
radiance = 1
[[lights]]
type = "point"
position = [0, 5, 0]
intensity = 1
)";
    auto scene = RunConfig::build(parse_config(text, "lights.toml", ".")).scene;
    ASSERT_EQ(scene->area_lights().size(), 2u);
    EXPECT_FALSE(scene->uses_embree());
    Rng rng(1, 1);
    const Ray up{Vec3::Zero(), Vec3::UnitY()};
    EXPECT_EQ(scene->transmittance(up, 10.0, rng), 0.0);   // both block the point light
    EXPECT_EQ(scene->transmittance(up, 1.0 - 1e-9, rng, scene->lights[0].get()), 1.0);
    EXPECT_EQ(scene->transmittance(up, 2.5, rng, scene->lights[1].get()), 0.0);   // the quad is in front
    const Ray sideways{Vec3(2, 2, 0), Vec3::UnitY()};
    EXPECT_EQ(scene->transmittance(sideways, 10.0, rng), 1.0);
    SurfaceHit hit;
    ASSERT_TRUE(scene->intersect(up, kInfinity, hit));
    EXPECT_EQ(hit.emitter, scene->lights[0].get());
    EXPECT_NEAR(hit.t, 1.0, 1e-12);
    EXPECT_EQ(hit.reflectance.maxCoeff(), 0.0);
    EXPECT_EQ(hit.emitted[0], 1.0);
    ASSERT_TRUE(scene->intersect(Ray{Vec3(0, 2, 0), Vec3::UnitY()}, kInfinity, hit));
    EXPECT_EQ(hit.emitter, scene->lights[1].get());
    EXPECT_NEAR(hit.t, 0.5, 1e-12);
    EXPECT_FALSE(scene->intersect(up, 0.5, hit));
    // Area lights are part of what can be lit.
    EXPECT_NEAR(scene->bounds.hi.y(), 3.5, 1e-12);
}

TEST(AreaLights, SphereConfigErrors) {
    EXPECT_THROW(light_from("[[lights]]\ntype='sphere'\ncenter=[0,0,0]\nradius=0\nradiance=1\n"), ConfigError);
    EXPECT_THROW(light_from("[[lights]]\ntype='sphere'\ncenter=[0,0,0]\nradius=1\nradiance=-1\n"), ConfigError);
    EXPECT_THROW(light_from("[[lights]]\ntype='sphere'\nradius=1\nradiance=1\n"), ConfigError);
    try {
        light_from("[[lights]]\ntype='sphere'\ncenter=[0,0,0]\nradius=-2\nradiance=1\n");
        FAIL();
    } catch (const ConfigError& e) {
        EXPECT_NE(std::string(e.what()).find("radius"), std::string::npos) << e.what();
    }
}

TEST(AreaLights, SphereAndFarQuadPhotonsAimAtWhatTheLightCanLight) {
    // A sphere light far from a small box (issue 20: 99.5% of a sphere light's photons reached
    // nothing and its map was 1.4% high from smoothing): half of its photons leave in the cone towards
    // the box, each carrying L cos A / p_mix. The mean power stays pi A L, and the power sent into
    // directions that meet the box's bounding sphere is the cosine emission's (4 combined SE).
    // The same for a small quad far above a box (the quad emits downwards).
    for (const auto& [text, box] : {std::pair<const char*, Bounds3>{kSphere, Bounds3{Vec3(6, 5, 4), Vec3(7, 6, 5)}},
                                    std::pair<const char*, Bounds3>{kQuad, Bounds3{Vec3(-0.5, -8, -0.5), Vec3(0.5, -7, 0.5)}}}) {
        auto aimed = light_from(text), classic = light_from(text);
        aimed->set_scene_bounds(box);
        const Vec3 c = 0.5 * (box.lo + box.hi);
        const double r = 0.5 * (box.hi - box.lo).norm();
        auto towards_box = [&](const Ray& ray) {
            const Vec3 oc = ray.origin - c;
            const double b = oc.dot(ray.dir);
            return b < 0.0 && (oc - b * ray.dir).squaredNorm() < r * r;
        };
        Rng rng(21, 3);
        test::Sample power, hit_aimed, hit_classic, share;
        for (int i = 0; i < 400000; ++i) {
            const EmissionSample a = aimed->sample_emission(rng);
            const EmissionSample s = classic->sample_emission(rng);
            power.add(a.power[0]);
            hit_aimed.add(towards_box(a.ray) ? a.power[0] : 0.0);
            hit_classic.add(towards_box(s.ray) ? s.power[0] : 0.0);
            share.add(towards_box(a.ray) ? 1.0 : 0.0);
            EmitterHit h;
            ASSERT_FALSE(aimed->intersect(a.ray, kInfinity, h) && a.power[0] > 0.0) << "a photon meeting its own light";
    }
    EXPECT_NEAR(power.mean(), aimed->power()[0], 4.0 * power.se());
    EXPECT_NEAR(hit_aimed.mean(), hit_classic.mean(), 4.0 * std::hypot(hit_aimed.se(), hit_classic.se()));
    EXPECT_GT(hit_classic.mean(), 0.0);
    EXPECT_LT(hit_aimed.se(), 0.25 * hit_classic.se());   // the point of aiming
    EXPECT_GT(share.mean(), 0.2) << text;
    }
}
