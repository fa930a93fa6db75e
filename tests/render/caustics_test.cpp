// Mirrors and glass in both integrators and the photon tracer (issue 42, docs/caustics.md): the
// dielectric furnace (a non-absorbing glass sphere, alone and inside a non-absorbing medium, under a
// constant sky renders the sky), energy conservation and caustic photons in the photon pass, a
// mirror's beam, and the photon map against the path tracer on the glass-sphere caustic scene.
#include <gtest/gtest.h>

#include "core/sampling/rng.h"
#include "photon/trace/photon_tracer.h"
#include "render/run/run.h"
#include "render/run/run_config.h"
#include "support/render_statistics.h"
#include "support/scene_from_config.h"

using namespace vpm;
using vpm::test::Sample;

namespace {

Sample ray_estimate(const Integrator& integrator, const Ray& ray, int n, uint64_t seed) {
    Sample s;
    for (int i = 0; i < n; ++i) {
        Rng rng(seed, uint64_t(i));
        s.add(integrator.radiance(ray, rng)[1]);
    }
    return s;
}

std::unique_ptr<Integrator> prepared(const RunConfig& config) {
    auto integrator = config.create_integrator();
    RunStats stats;
    PassContext context;
    context.progress = false;
    integrator->prepare(context, stats);
    return integrator;
}

const char* kGlassUnderSky = R"(
[camera]
position = [0, 0, 4]
look_at = [0, 0, 0]
[[lights]]
type = "environment"
radiance = 1.5
[[shapes]]
type = "sphere"
center = [0, 0, 0]
radius = 0.6
material = "dielectric"
ior = 1.5
)";

// Rays through the centre, off it, and near the rim (mostly reflected, many internal reflections).
const Ray kRays[] = {Ray{Vec3(0, 0, 4), Vec3(0, 0, -1)}, Ray{Vec3(0.3, 0.1, 4), Vec3(0, 0, -1)},
                     Ray{Vec3(0.59, 0, 4), Vec3(0, 0, -1)}, Ray{Vec3(0, 0, 4), Vec3(0.12, 0.05, -1).normalized()}};

}  // namespace

// Russian roulette off (rr_depth 2^20) in the clear-glass tests below: every camera path then ends
// in the sky with weight exactly 1 / eta^2 * eta^2 = 1, so the sky must be seen to rounding, and a
// path that enters the glass and never leaves it (weight 1 / eta^2) fails at once. With the
// roulette on, the path tracer's roulette inside glass survives with 0.999 (it judges throughput
// over the refractions' 1 / eta^2, transport/walk_steps.h): survivors weigh 1 / 0.999^k and about
// one path in 20000 is ended, so a run without that one path reads +5e-5 with a sample standard
// error of 3.5e-6 that cannot see it. The roulette's expectation is tested in walk_steps_test.cpp
// and inside glass by the furnace below.
constexpr const char* kRouletteOff = "render.rr_depth=1048576";

TEST(Caustics, GlassSphereUnderAConstantSkyIsInvisible) {
    // Every chain of reflections and refractions through clear glass ends in the sky: each camera
    // path weighs 1 / eta^2 * eta^2 = 1, so the sky is seen unchanged.
    for (const char* integrator : {"render.integrator=path", "render.integrator=photon_map"}) {
        const RunConfig config =
            RunConfig::build(parse_config(kGlassUnderSky, "glass.toml", ".", {integrator, kRouletteOff}));
        const auto pt = prepared(config);
        for (const Ray& ray : kRays) {
            const Sample s = ray_estimate(*pt, ray, 20000, 3);
            EXPECT_NEAR(s.mean(), 1.5, 1e-9) << integrator << " ray " << ray.origin.transpose();
        }
    }
}

TEST(Caustics, GlassSphereInsideANonAbsorbingMediumIsAFurnace) {
    // The medium continues inside the glass (docs/caustics.md). At equilibrium the radiance inside
    // the glass is eta^2 times the sky's; the camera path carries 1 / eta^2 in and eta^2 out.
    const std::string text = std::string(kGlassUnderSky) + R"(
[[media]]
type = "homogeneous"
shape = "sphere"
radius = 1.0
sigma_t_scale = 2.0
albedo = 1.0
g = 0.5
[photons]
count = 200000
)";
    for (const char* overrides : {"render.mis=true", "render.mis=false"}) {
        const RunConfig config = RunConfig::build(parse_config(text, "glass_fog.toml", ".", {"render.integrator=path", overrides}));
        const auto pt = prepared(config);
        for (const Ray& ray : kRays) {
            const Sample s = ray_estimate(*pt, ray, 20000, 5);
            EXPECT_NEAR(s.mean(), 1.5, 3.0 * s.se()) << overrides << " ray " << ray.origin.transpose();
            EXPECT_LT(s.se(), 0.015 * 1.5) << overrides;   // decisive: a factor eta^2 = 2.25 inside is far out
        }
    }
    // The photon map is not checked here: in this dense albedo-1 furnace its own bias at 200000
    // photons is 15% and moves with any shape added (docs/caustics.md); the glass-sphere scene below
    // compares it with the path tracer instead.
}

TEST(Caustics, PhotonsCrossGlassAndMirrorsWithoutLosingEnergyAndAreStoredAsCaustics) {
    // A point light over a glass sphere over a floor, a mirror beside, in fog. With store_direct =
    // false every stored photon has scattered or crossed a specular surface; the floor's spot under
    // the sphere is lit only through the glass, so it holds surface photons; the energy balance is exact.
    const auto scene = test::scene_from_config(R"(
[camera]
position = [0, 1, 4]
look_at = [0, 1, 0]
[[lights]]
type = "point"
position = [0, 3, 0]
intensity = 10
[[media]]
type = "homogeneous"
shape = "box"
min = [-2, 0, -2]
max = [2, 3.5, 2]
sigma_t_scale = 0.2
albedo = 0.9
g = 0.3
[[shapes]]
type = "sphere"
center = [0, 1.5, 0]
radius = 0.5
material = "dielectric"
[[shapes]]
type = "quad"
center = [1.5, 1, 0]
u = [0, 1, 0]
v = [0, 0, 1]
material = "mirror"
reflectance = 0.9
[[shapes]]
type = "quad"
center = [0, 0, 0]
u = [2, 0, 0]
v = [0, 0, -2]
reflectance = 0.5
)");
    PhotonTraceSettings s;
    s.count = 100000;
    s.store_direct = false;
    s.store_surface = true;
    s.progress = false;
    const PhotonTraceResult r = trace_photons(*scene, s);
    EXPECT_LT(r.energy.relative_imbalance(), 1e-9);
    size_t under_sphere = 0;
    for (const PhotonInput& p : r.surface_photons)
        if (p.position.head<1>().norm() < 0.3 && std::abs(p.position.z()) < 0.3) ++under_sphere;
    EXPECT_GT(under_sphere, 1000u);   // the caustic's focus
    // Glass alone conserves the power it passes: without fog and floor, every photon that meets the
    // sphere leaves it (the energy escapes: nothing is absorbed).
    const auto clear = test::scene_from_config(R"(
[camera]
position = [0, 0, 4]
look_at = [0, 0, 0]
[[lights]]
type = "point"
position = [0, 3, 0]
intensity = 10
[[shapes]]
type = "sphere"
center = [0, 1.5, 0]
radius = 0.5
material = "dielectric"
)");
    const PhotonTraceResult c = trace_photons(*clear, s);
    EXPECT_LT(c.energy.relative_imbalance(), 1e-9);
    EXPECT_EQ(c.energy.absorbed.maxCoeff(), 0.0);
    EXPECT_GT(c.surface_hits, 50000u);   // the light aims at the sphere: most photons meet it, often twice
}

TEST(Caustics, PhotonMapAgreesWithThePathTracerOnTheGlassSphereInFog) {
    // configs/glass_sphere_fog.toml small, its light a sphere of radius 0.1 (the path tracer finds it
    // through the glass by phase and floor samples; its image converges, slowly). The mean over the
    // image holds the cone in the fog and the spot on the floor: both integrators agree on it.
    const std::string path = VPM_SOURCE_DIR "/configs/glass_sphere_fog.toml";
    const std::vector<std::string> small = {"render.width=16", "render.height=16", "lights.0.radius=0.1", "lights.0.radiance=320"};
    std::vector<std::string> pt = small, pm = small;
    pt.insert(pt.end(), {"render.integrator=\"path\"", "render.spp=256", "render.seed=3"});
    pm.insert(pm.end(), {"render.integrator=\"photon_map\"", "render.spp=16", "photons.count=200000", "render.seed=4"});
    const Sample a = test::repeated_run_brightness(RunConfig::load(path, pt), 6);
    const Sample b = test::repeated_run_brightness(RunConfig::load(path, pm), 6);
    const double se = std::hypot(a.se(), b.se());
    EXPECT_NEAR(b.mean(), a.mean(), 4.0 * se + 0.02 * a.mean()) << "path " << a.mean() << " +- " << a.se() << ", photon map "
                                                               << b.mean() << " +- " << b.se();
    EXPECT_LT(se, 0.03 * a.mean());   // decisive against losing the light that crosses the glass
}

// Shapes of every scale in one scene (issue 61): rays leave each surface by an offset of its own
// scale. A clear glass sphere of radius 1e-6 under a sky of 0.5 stays invisible next to a far
// mirror quad of half-size 10 (with offsets of 1e-6 of the scene's extent, larger than the sphere,
// paths entered the glass and never left it: 1 / eta^2 of the sky).
TEST(Caustics, TinyGlassSphereBesideALargeMirrorIsInvisible) {
    const char* text = R"(
[camera]
position = [0, 0, 1]
look_at = [0, 0, 0]
fov = 1.2e-4
[[lights]]
type = "environment"
radiance = 0.5
[[shapes]]
type = "sphere"
center = [0, 0, 0]
radius = 1e-6
material = "dielectric"
ior = 1.5
[[shapes]]
type = "quad"
center = [0, 0, -100]
u = [10, 0, 0]
v = [0, 10, 0]
material = "mirror"
)";
    // Rays from a unit distance: they meet the sphere (from 4 radii, offsets of 1e-6 of the scene's
    // extent, 5.5e-5, skipped it whole).
    const double r = 1e-6;
    const Ray rays[] = {Ray{Vec3(0, 0, 1), Vec3(0, 0, -1)}, Ray{Vec3(0.3 * r, 0.1 * r, 1), Vec3(0, 0, -1)},
                        Ray{Vec3(0.59 * r, 0, 1), Vec3(0, 0, -1)}, Ray{Vec3(0.9 * r, 0.3 * r, 1), Vec3(0, 0, -1)}};
    for (const char* integrator : {"render.integrator=path", "render.integrator=photon_map"}) {
        const RunConfig config = RunConfig::build(parse_config(text, "tiny_glass.toml", ".", {integrator, kRouletteOff}));
        const auto pt = prepared(config);
        for (const Ray& ray : rays) {
            const Sample s = ray_estimate(*pt, ray, 20000, 61);
            EXPECT_NEAR(s.mean(), 0.5, 1e-9) << integrator << " ray " << ray.origin.transpose();
        }
    }
}

// configs/glass_sphere_fog.toml with a black sphere of radius 1e6 far below, which no camera ray
// or photon reaches before leaving the fog: the image is the scene's without it (it read -10.3%
// with offsets of 1e-6 of the scene's extent, here 1 unit: more than the glass sphere's radius).
TEST(Caustics, AFarHugeSphereLeavesTheGlassSphereInFogAlone) {
    const std::string path = VPM_SOURCE_DIR "/configs/glass_sphere_fog.toml";
    const std::vector<std::string> small = {"render.width=16", "render.height=16", "render.spp=4", "photons.count=50000",
                                            "render.seed=5"};
    std::vector<std::string> huge = small;
    huge.push_back("shapes=[{type=\"sphere\", center=[0,1.5,0], radius=0.5, material=\"dielectric\", ior=1.5}, "
                   "{type=\"quad\", center=[0,0,0], u=[2,0,0], v=[0,0,-2], reflectance=0.5}, "
                   "{type=\"sphere\", center=[0,-3e6,0], radius=1e6, material=\"black\"}]");
    const Sample a = test::repeated_run_brightness(RunConfig::load(path, small), 6);
    const Sample b = test::repeated_run_brightness(RunConfig::load(path, huge), 6);
    const double se = std::hypot(a.se(), b.se());
    EXPECT_NEAR(b.mean(), a.mean(), 3.0 * se) << "without " << a.mean() << " +- " << a.se() << ", with " << b.mean() << " +- "
                                              << b.se();
    EXPECT_LT(se, 0.02 * a.mean());   // decisive against the 10% it lost
}
