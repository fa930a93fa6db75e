// Photon density estimates that do not mix photons across glass interfaces (issue 57,
// docs/interface_regions.md): the photon tracer's regions agree with where its photons lie, and
// the glass furnaces (non-absorbing fog around and inside clear glass, under a constant sky) read
// the exact answer within 3 standard errors over independent photon maps.
#include <gtest/gtest.h>

#include <cmath>

#include <cstdio>

#include "photon/estimate/kernels.h"
#include "photon/map/region_photon_maps.h"
#include "photon/trace/photon_tracer.h"
#include "render/photon_map/gathers/photon_beams_gather.h"
#include "render/photon_map/gathers/point_beam_gather.h"
#include "render/photon_map/photon_map_integrator.h"
#include "render/run/run.h"
#include "render/run/run_config.h"
#include "scene/dielectric_regions.h"
#include "support/render_statistics.h"
#include "support/scene_from_config.h"

using namespace vpm;
using vpm::test::Sample;

namespace {

const char* kFog = R"(
[[lights]]
type = "environment"
radiance = 1.0
[[media]]
type = "homogeneous"
shape = "sphere"
radius = 1.5
sigma_t_scale = 1.0
albedo = 1.0
g = 0.5
)";

const char* kCamera = R"(
[camera]
position = [0, 0, 4]
look_at = [0, 0, 0]
)";

std::string glass_sphere(double x, double y, double z, double radius) {
    return "[[shapes]]\ntype = \"sphere\"\ncenter = [" + std::to_string(x) + ", " + std::to_string(y) + ", " +
           std::to_string(z) + "]\nradius = " + std::to_string(radius) + "\nmaterial = \"dielectric\"\nior = 1.5\n";
}

const std::string kGlassBox = R"(
[[shapes]]
type = "box"
min = [-0.7, -0.6, -0.5]
max = [0.6, 0.7, 0.8]
material = "dielectric"
ior = 1.5
)";

// Distance from x to the nearest glass sphere's surface or box face (the shapes of these tests).
double near_interface(const Scene& scene, const Vec3& x) {
    double d = kInfinity;
    for (const DielectricShape& s : scene.surfaces->dielectric_shapes()) {
        if (s.sphere) {
            d = std::min(d, std::abs((x - s.center).norm() - s.radius));
        } else {
            const Vec3 lo = x - s.bounds.lo, hi = s.bounds.hi - x;
            d = std::min(d, std::min(lo.cwiseAbs().minCoeff(), hi.cwiseAbs().minCoeff()));
        }
    }
    return d;
}

// Image means over `maps` independent photon maps (stream offsets 0 ..), each rendered twice on
// the same camera samples: `split`, the estimates counting their own region's photons only (the
// renderer's), and `mixed`, one map of all photons (what it did before regions).
struct Furnace {
    Sample split, mixed;
};
Furnace furnace_pair(const std::string& text, int maps, const std::vector<std::string>& extra = {}, bool mixed = false,
                     int spp = 2) {
    // direct = "photon_map": every collision stored, so the photon density is constant on each side of
    // an interface and the split estimate is exact in expectation. With "nee" the scattered photons
    // thin out towards the fog's edge, and the ball clipped at the glass reads that gradient to first
    // order: -0.35% +- 0.06% at k = 32 (docs/interface_regions.md).
    std::vector<std::string> o = {"render.integrator=\"photon_map\"", "render.width=16", "render.height=16",
                                  "photons.count=50000", "photons.k=32", "photons.estimator=\"corrected\"",
                                  "photons.gather=\"collision\"", "photons.direct=\"photon_map\""};
    o.insert(o.end(), extra.begin(), extra.end());
    const RunConfig config = RunConfig::build(parse_config(text, "glass_furnace.toml", ".", o));
    const PhotonMapSettings& ps = photon_map_settings(config);
    const bool surface = config.scene->uses_embree() && !ps.final_gather;
    Furnace f;
    for (int r = 0; r < maps; ++r) {
        PhotonTraceSettings ts;
        ts.count = uint64_t(ps.count);
        ts.stream_offset = uint64_t(r);
        ts.progress = false;
        ts.store_direct = ps.direct == DirectLighting::photon_map;
        ts.store_surface = surface;
        const PhotonTraceResult traced = trace_photons(*config.scene, ts);
        const PhotonMap volume(traced.photons), surfaces(traced.surface_photons);
        const RegionPhotonMaps volume_regions(traced.photons, traced.photon_regions);
        const RegionPhotonMaps surface_regions(traced.surface_photons, traced.surface_photon_regions);
        PhotonMapIntegrator split(*config.scene, ps, volume, surface ? &surfaces : nullptr);
        split.use_regions(&volume_regions, surface ? &surface_regions : nullptr);
        f.split.add(test::image_mean(config, split, 1000 + uint64_t(r), spp));
        if (mixed)
            f.mixed.add(test::image_mean(config, PhotonMapIntegrator(*config.scene, ps, volume, surface ? &surfaces : nullptr),
                                         1000 + uint64_t(r), spp));
    }
    return f;
}

// The renderer's own runs (its photon pass builds the region maps), `maps` stream offsets.
Sample furnace(const std::string& text, int maps, const std::vector<std::string>& extra = {}) {
    std::vector<std::string> o = {"render.integrator=\"photon_map\"", "render.width=16", "render.height=16", "render.spp=2",
                                  "photons.count=50000", "photons.k=32", "photons.estimator=\"corrected\""};
    o.insert(o.end(), extra.begin(), extra.end());
    return test::repeated_run_brightness(RunConfig::build(parse_config(text, "glass_furnace.toml", ".", o)), maps);
}

const std::string kCameraInGlass = R"(
[camera]
position = [0, 0, 0.3]
look_at = [0, 0, -1]
)";

const std::string kWhiteSphere = R"(
[[shapes]]
type = "sphere"
center = [0.1, 0, 0]
radius = 0.4
reflectance = 1.0
)";

struct FurnaceCase {
    const char* name;
    std::string text;
    double exact;
    // The relative standard error 12 maps reach (the CI check's resolution). Inside the glass few
    // photon walks enter, each stores many photons (trapped by total internal reflection): one map
    // scatters by 7% there.
    double resolution = 0.005;
};

// The furnaces: non-absorbing fog (radius 1.5) under a sky of 1, with clear glass in it; a white
// Lambertian sphere inside the glass (reflectance 1) for the surface map. Exact: 1 seen from outside,
// eta^2 = 2.25 from inside the glass.
std::vector<FurnaceCase> furnace_cases() {
    return {
        {"sphere", std::string(kCamera) + kFog + glass_sphere(0, 0, 0, 1.0), 1.0},
        {"camera_in_glass", std::string(kCameraInGlass) + kFog + glass_sphere(0, 0, 0, 1.0), 2.25, 0.025},
        {"box", std::string(kCamera) + kFog + kGlassBox, 1.0},
        {"nested", std::string(kCamera) + kFog + glass_sphere(0, 0, 0, 1.0) + glass_sphere(0.2, 0, 0, 0.5), 1.0},
        {"touching", std::string(kCamera) + kFog + glass_sphere(-0.6, 0, 0, 0.6) + glass_sphere(0.6, 0, 0, 0.6), 1.0},
        {"surface_in_glass", std::string(kCamera) + kFog + glass_sphere(0, 0, 0, 1.0) + kWhiteSphere, 1.0},
    };
}

}  // namespace

TEST(GlassRegions, PhotonsCarryTheRegionTheyLieIn) {
    // Lights outside (the sky) and inside glass (a sphere light in a glass sphere), nested and
    // touching spheres and a box: every stored photon's tracked region is the one a point test gives
    // at its position (photons within 1e-6 of an interface aside: round-off may put them either side).
    const std::string inner_light = R"(
[[lights]]
type = "sphere"
center = [0.5, 0, 0]
radius = 0.1
radiance = 5.0
)";
    const std::vector<std::string> scenes = {
        glass_sphere(0, 0, 0, 1.0),
        glass_sphere(0, 0, 0, 1.0) + glass_sphere(0.2, 0, 0, 0.5),
        glass_sphere(-0.6, 0, 0, 0.6) + glass_sphere(0.6, 0, 0, 0.6),
        kGlassBox,
        glass_sphere(0, 0, 0, 1.0) + inner_light,
    };
    for (const std::string& shapes : scenes) {
        const auto scene = test::scene_from_config(std::string(kCamera) + kFog + shapes);
        PhotonTraceSettings s;
        s.count = 20000;
        s.progress = false;
        s.store_surface = true;
        const PhotonTraceResult r = trace_photons(*scene, s);
        ASSERT_EQ(r.photon_regions.size(), r.photons.size());
        size_t checked = 0, wrong = 0, inside = 0;
        for (size_t i = 0; i < r.photons.size(); ++i) {
            const Vec3& x = r.photons[i].position;
            if (near_interface(*scene, x) < 1e-6) continue;
            ++checked;
            if (r.photon_regions[i] != region_at(scene->surfaces.get(), x)) ++wrong;
            if (r.photon_regions[i] != 0) ++inside;
        }
        EXPECT_EQ(wrong, 0u) << shapes;
        EXPECT_GT(checked, 10000u) << shapes;
        EXPECT_GT(inside, 1000u) << shapes;   // the glass holds photons: the check is not vacuous
    }
}

TEST(GlassRegions, BallFractionIsTheLensVolumeAndItsQuadrature) {
    // A ball centred on a sphere's surface: the exact lens gives its inside share; the point
    // quadrature (used with two crossing surfaces and with meshes) agrees with it to its resolution.
    const auto one = test::scene_from_config(std::string(kCamera) + kFog + glass_sphere(0, 0, 0, 1.0));
    const auto two = test::scene_from_config(std::string(kCamera) + kFog + glass_sphere(0, 0, 0, 1.0) +
                                             glass_sphere(0, 0, 3.0, 0.5));   // a second sphere, far, makes it quadrature only if it crosses
    const Vec3 x(0.99, 0, 0);
    const double r = 0.2;
    const double in = region_ball_fraction(one->surfaces.get(), x, r, 1), out = region_ball_fraction(one->surfaces.get(), x, r, 0);
    EXPECT_NEAR(in + out, 1.0, 1e-12);
    // The lens of two spheres (radii r and R, centres d apart), in its textbook closed form.
    const double d = 0.99, R = 1.0;
    const double lens = kPi * (R + r - d) * (R + r - d) * (d * d + 2 * d * r - 3 * r * r + 2 * d * R + 6 * r * R - 3 * R * R) / (12 * d);
    EXPECT_NEAR(in, lens / (4.0 / 3.0 * kPi * r * r * r), 1e-9);
    EXPECT_EQ(region_ball_fraction(two->surfaces.get(), x, r, 1), in);   // the far sphere does not cross
    const auto box = test::scene_from_config(std::string(kCamera) + kFog + kGlassBox);
    const double box_in = region_ball_fraction(box->surfaces.get(), Vec3(0.59, 0, 0), 0.1, 1);
    const double cap = kPi * 0.09 * 0.09 * (0.3 - 0.09) / 3.0 / (4.0 / 3.0 * kPi * 0.001);
    EXPECT_NEAR(box_in, 1.0 - cap, 0.02);   // 256 points: the share to about 1%
}

TEST(GlassRegions, DiscFractionIsTheCirclesOverlapAndItsQuadrature) {
    // The surface map's disc (a floor crossing glass): against one sphere the overlap of the disc with
    // the sphere's circle in the disc's plane, in closed form; against a box's face the 128-point
    // quadrature gives the straight chord's share.
    const auto one = test::scene_from_config(std::string(kCamera) + kFog + glass_sphere(0, 0, 0, 1.0));
    const Vec3 up(0, 0, 1);
    const double r = 0.2, h = 0.3, rho = std::sqrt(1.0 - h * h), d = 0.9;   // plane z = h cuts a circle of radius rho
    const Vec3 x(d, 0, h);
    const double in = region_disc_fraction(one->surfaces.get(), x, up, r, 1), out = region_disc_fraction(one->surfaces.get(), x, up, r, 0);
    EXPECT_NEAR(in + out, 1.0, 1e-12);
    // Two circles' lens area, term by term (radii r and rho, centres d apart).
    const double lens = r * r * std::acos((d * d + r * r - rho * rho) / (2 * d * r)) +
                        rho * rho * std::acos((d * d + rho * rho - r * r) / (2 * d * rho)) -
                        0.5 * std::sqrt((-d + r + rho) * (d + r - rho) * (d - r + rho) * (d + r + rho));
    EXPECT_NEAR(in, lens / (kPi * r * r), 1e-9);
    EXPECT_GT(in, 0.2);
    EXPECT_LT(in, 0.8);
    EXPECT_EQ(region_disc_fraction(one->surfaces.get(), Vec3(0, 0, 0.5), up, 0.1, 1), 1.0);   // wholly inside
    const auto box = test::scene_from_config(std::string(kCamera) + kFog + kGlassBox);
    const Vec3 floor_normal(0, 1, 0);
    // A disc on the plane y = 0 centred 0.05 inside the face x = 0.6: the chord leaves 0.1955 outside.
    const double chord = (std::acos(0.5) * 0.01 - 0.05 * std::sqrt(0.01 - 0.0025)) / (kPi * 0.01);
    EXPECT_NEAR(region_disc_fraction(box->surfaces.get(), Vec3(0.55, 0, 0), floor_normal, 0.1, 1), 1.0 - chord, 0.02);
    EXPECT_NEAR(region_disc_fraction(box->surfaces.get(), Vec3(0.65, 0, 0), floor_normal, 0.1, 0), 1.0 - chord, 0.02);
    EXPECT_EQ(region_disc_fraction(box->surfaces.get(), Vec3(2.0, 0, 0), floor_normal, 0.1, 0), 1.0);   // glass out of reach
}

TEST(GlassRegions, GlassSphereInFogIsAFurnace) {
    // 48 maps, each rendered split by region and mixed (one map of all photons, as before regions) on
    // the same camera samples: split within 3 standard errors of 1 at SE <= 0.15%; mixed reads high.
    const Furnace f = furnace_pair(std::string(kCamera) + kFog + glass_sphere(0, 0, 0, 1.0), 48, {"render.width=32", "render.height=32"}, true);
    std::printf("glass sphere furnace, 48 maps: split %.5f +- %.5f, mixed %.5f +- %.5f\n", f.split.mean(), f.split.se(), f.mixed.mean(), f.mixed.se());
    EXPECT_NEAR(f.split.mean(), 1.0, 3.0 * f.split.se());
    EXPECT_LT(f.split.se(), 0.0015);
    EXPECT_GT(f.mixed.mean() - 1.0, 3.0 * f.mixed.se());   // the test sees the mixing it guards against
}

TEST(GlassRegions, TheRenderersOwnRunsSplitByRegion) {
    // The photon pass builds the region maps itself (8 runs, SE about 0.4%: a pass that did not split
    // reads +1.5%, 4 SE).
    const Sample s = furnace(std::string(kCamera) + kFog + glass_sphere(0, 0, 0, 1.0), 8, {"render.width=32", "render.height=32", "photons.gather=\"collision\""});
    std::printf("renderer's runs: %.5f +- %.5f\n", s.mean(), s.se());
    EXPECT_NEAR(s.mean(), 1.0, 3.0 * s.se());
}

TEST(GlassRegions, GlassFurnacesReadTheExactAnswer) {
    // Each case over 12 maps (standard errors 0.3-0.5%, 2% seen from inside the glass): box (the
    // ball's share by quadrature), nested and touching spheres, the camera inside the glass, and the
    // surface map inside it.
    for (const FurnaceCase& c : furnace_cases()) {
        if (std::string(c.name) == "sphere") continue;   // above, at full power
        const Furnace f = furnace_pair(c.text, 12);
        std::printf("%-17s %.5f +- %.5f (exact %.2f)\n", c.name, f.split.mean(), f.split.se(), c.exact);
        EXPECT_NEAR(f.split.mean(), c.exact, 3.0 * f.split.se()) << c.name;
        EXPECT_LT(f.split.se(), c.resolution * c.exact) << c.name;
    }
}

// The measurement behind docs/interface_regions.md (minutes): every case over 64 maps, split and mixed
// on the same maps and camera samples, for the collision and the march gathers.
//   build/test_render --gtest_also_run_disabled_tests --gtest_filter='GlassRegions.DISABLED_*'
TEST(GlassRegions, DISABLED_SphereFurnaceMeasurement) {
    for (int maps : {256}) {
        const Furnace f = furnace_pair(std::string(kCamera) + kFog + glass_sphere(0, 0, 0, 1.0), maps, {"render.width=32", "render.height=32"}, true);
        std::printf("sphere, %d maps, 32x32 x 2 spp: split %.5f +- %.5f, mixed %.5f +- %.5f\n", maps, f.split.mean(), f.split.se(),
                    f.mixed.mean(), f.mixed.se());
    }
}

TEST(GlassRegions, DISABLED_SphereFurnaceByIorAndK) {
    for (const char* ior : {"1.0001", "1.5"})
        for (const char* k : {"photons.k=8", "photons.k=32", "photons.k=128"}) {
            std::string glass = glass_sphere(0, 0, 0, 1.0);
            glass.replace(glass.find("ior = 1.5"), 9, std::string("ior = ") + ior);
            const Furnace f = furnace_pair(std::string(kCamera) + kFog + glass, 128, {"render.width=32", "render.height=32", k}, true);
            std::printf("ior %s, %s, 128 maps: split %.5f +- %.5f, mixed %.5f +- %.5f\n", ior, k, f.split.mean(), f.split.se(),
                        f.mixed.mean(), f.mixed.se());
            std::fflush(stdout);
        }
}

TEST(GlassRegions, DISABLED_SphereFurnaceAllPhotonsStored) {
    // photons.direct = "photon_map": every collision stored, so the photon density is constant on
    // each side of the interface (with "nee" the scattered photons thin out towards the fog's edge).
    for (const char* k : {"photons.k=32", "photons.k=128"}) {
        const Furnace f = furnace_pair(std::string(kCamera) + kFog + glass_sphere(0, 0, 0, 1.0), 128,
                                       {"render.width=32", "render.height=32", k, "photons.direct=\"photon_map\""}, true);
        std::printf("ior 1.5, direct photon_map, %s, 128 maps: split %.5f +- %.5f, mixed %.5f +- %.5f\n", k, f.split.mean(),
                    f.split.se(), f.mixed.mean(), f.mixed.se());
        std::fflush(stdout);
    }
}

TEST(GlassRegions, DISABLED_FurnaceMeasurementAllPhotonsStored) {
    // The CI cases' settings (direct = "photon_map", 16 x 16, 2 spp) over 64 maps.
    for (const FurnaceCase& c : furnace_cases()) {
        const Furnace f = furnace_pair(c.text, 64, {}, true);
        std::printf("| %s | %.2f | %.5f +- %.5f (%+.1f SE) | %.5f +- %.5f (%+.1f SE) |\n", c.name, c.exact, f.split.mean(),
                    f.split.se(), (f.split.mean() - c.exact) / f.split.se(), f.mixed.mean(), f.mixed.se(),
                    (f.mixed.mean() - c.exact) / f.mixed.se());
        std::fflush(stdout);
    }
}

TEST(GlassRegions, DISABLED_FurnaceMeasurement) {
    for (const char* gather : {"photons.gather=\"collision\"", "photons.gather=\"march\""})
        for (const FurnaceCase& c : furnace_cases()) {
            const Furnace f = furnace_pair(c.text, 64, {gather, "photons.direct=\"nee\""}, true);
            std::printf("| %s | %s | %.2f | %.5f +- %.5f (%+.1f SE) | %.5f +- %.5f (%+.1f SE) |\n", gather + 15, c.name, c.exact,
                        f.split.mean(), f.split.se(), (f.split.mean() - c.exact) / f.split.se(), f.mixed.mean(), f.mixed.se(),
                        (f.mixed.mean() - c.exact) / f.mixed.se());
            std::fflush(stdout);
        }
}

// A point light inside a glass sphere (radius 0.5) of transmittance 0, in fog (radius 1.5).
const std::string kSealedLight = std::string(kCamera) + R"(
[[lights]]
type = "point"
position = [0, 0, 0]
intensity = 10.0
[[media]]
type = "homogeneous"
shape = "sphere"
radius = 1.5
sigma_t_scale = 1.0
albedo = 0.9
g = 0.5
[[shapes]]
type = "sphere"
center = [0, 0, 0]
radius = 0.5
material = "dielectric"
transmittance = 0.0
)";

TEST(GlassRegions, ALightSealedInOpaqueGlassLightsNothingOutside) {
    // No light leaves the glass, so the fog outside is black (the path tracer reads exactly 0). Its
    // photons are all stored inside; counted by an outside query they lit the fog (image mean
    // 0.00161 +- 0.00002).
    const std::string& text = kSealedLight;
    for (const char* direct : {"photons.direct=\"nee\"", "photons.direct=\"photon_map\""}) {
        const Sample s = furnace(text, 2, {direct});
        EXPECT_EQ(s.mean(), 0.0) << direct;
    }
}

TEST(GlassRegions, SegmentGathersOfASealedLightLightNothingOutside) {
    // The segment gathers split by region: a camera segment outside the glass crosses no disc or beam
    // of the photons inside, and with none of its own region it is gathered as the collision gather's
    // (the path goes on: black here). Exactly 0, as the path tracer.
    const std::vector<std::vector<std::string>> cases = {
        {"photons.gather=\"point_beam\"", "photons.direct=\"nee\""},
        {"photons.gather=\"point_beam\"", "photons.direct=\"photon_map\""},
        {"photons.gather=\"photon_beams\"", "photons.direct=\"photon_map\""},
        {"photons.gather=\"photon_beams\"", "photons.beam_widths=\"sample_point\""}};
    for (std::vector<std::string> c : cases) {
        c.push_back("photons.count=10000");
        const Sample s = furnace(kSealedLight, 1, c);
        EXPECT_EQ(s.mean(), 0.0) << c[0] << " " << c[1];
    }
}

TEST(GlassRegions, UnsplitSegmentGathersLeakTheSealedLight) {
    // What the split guards against, on the gathers themselves: the same photons and beams, one
    // structure over all of them, give segments just outside the glass light from inside it (the
    // discs and beams' widths reach across the interface); split by region those segments have no
    // estimate of their own (starved) and 0.
    const RunConfig config = RunConfig::build(parse_config(kSealedLight, "sealed.toml", ".", {"photons.count=20000"}));
    const Scene& scene = *config.scene;
    PhotonTraceSettings ts;
    ts.count = 20000;
    ts.progress = false;
    ts.store_beams = true;
    const PhotonTraceResult traced = trace_photons(scene, ts);
    ASSERT_FALSE(traced.photons.empty());
    ASSERT_EQ(traced.beam_regions.size(), traced.beams.size());
    for (RegionMask r : traced.beam_regions) ASSERT_EQ(r, RegionMask(1));   // every flight inside the glass
    const PhotonMap map(traced.photons);
    const RegionPhotonMaps regions(traced.photons, traced.photon_regions);
    const Kernel kernel = Kernel::constant();
    const PointBeamGather discs(scene, map, 32, kernel, kInfinity, 0.0);
    const PointBeamGather discs_split(scene, map, 32, kernel, kInfinity, 0.0, 1.0, &regions);
    const PhotonBeamsGather beams(scene, traced.beams, BeamWidths::balloon, 32, false, kernel, kInfinity, 2.0);
    const PhotonBeamsGather beams_split(scene, traced.beams, BeamWidths::balloon, 32, false, kernel, kInfinity, 2.0,
                                        &traced.beam_regions);
    EXPECT_FALSE(discs.split_by_region());
    EXPECT_TRUE(discs_split.split_by_region() && beams_split.split_by_region());
    Rng rng(5, 0);
    double leaked_discs = 0.0, leaked_beams = 0.0;
    for (int i = 0; i < 32; ++i) {   // vertical segments through the fog at 0.502 .. 0.564 from the centre
        const double x = 0.502 + 0.002 * double(i);
        const Ray ray{Vec3(x, 0.0, 1.2), Vec3(0.0, 0.0, -1.0)};
        leaked_discs += discs.in_scattering(ray, 2.4, 0, rng).sum();
        leaked_beams += beams.in_scattering(ray, 2.4, 0, rng).sum();
        bool starved = false;
        EXPECT_EQ(discs_split.in_scattering(ray, 2.4, 0, rng, &starved).sum(), 0.0);
        EXPECT_TRUE(starved);
        starved = false;
        EXPECT_EQ(beams_split.in_scattering(ray, 2.4, 0, rng, &starved).sum(), 0.0);
        EXPECT_TRUE(starved);
    }
    std::printf("sealed light, 32 segments just outside the glass: unsplit discs %.4g, beams %.4g\n", leaked_discs,
                leaked_beams);
    EXPECT_GT(leaked_discs, 0.0);
    EXPECT_GT(leaked_beams, 0.0);
    // Inside the glass the split gathers read the same photons as the whole ones.
    const Ray inside{Vec3(0.1, 0.0, 0.4), Vec3(0.0, 0.0, -1.0)};
    Rng a(9, 0), b(9, 0);
    EXPECT_EQ(discs.in_scattering(inside, 0.8, 0, a).sum(), discs_split.in_scattering(inside, 0.8, 1, b).sum());
}

TEST(GlassRegions, PointBeamDiscsAreSplitByRegion) {
    // The glass furnace at ior 3.9 (inside the glass the photons are eta^2 = 15 times denser), every
    // collision stored, point_beam over 8 maps, split and mixed on the same maps and camera samples:
    // one disc BVH over all photons reads +7.0% +- 0.6% (the dense discs inside lit the fog outside);
    // split by region the mixing is gone (paired difference over 3 SE). What the split leaves is the
    // discs' boundary share (-1.4% +- 0.5%: near the glass a segment's discs lie partly beyond it,
    // where none of its region can be; not corrected, docs/interface_regions.md).
    std::string glass = glass_sphere(0, 0, 0, 1.0);
    glass.replace(glass.find("ior = 1.5"), 9, "ior = 3.9");
    const Furnace f = furnace_pair(std::string(kCamera) + kFog + glass, 8, {"photons.gather=\"point_beam\""}, true);
    std::printf("point_beam, ior 3.9, 8 maps: split %.5f +- %.5f, mixed %.5f +- %.5f\n", f.split.mean(), f.split.se(),
                f.mixed.mean(), f.mixed.se());
    EXPECT_GT(f.mixed.mean() - 1.0, 3.0 * f.mixed.se());
    EXPECT_GT(f.mixed.mean() - f.split.mean(), 3.0 * std::hypot(f.mixed.se(), f.split.se()));
}

// The segment gathers in the glass furnace, split (the renderer's) and mixed (one structure over all
// photons) on the same maps and camera samples: `build/test_render --gtest_also_run_disabled_tests
// --gtest_filter='GlassRegions.DISABLED_SegmentGatherFurnace*'`.
TEST(GlassRegions, DISABLED_SegmentGatherFurnaceMeasurement) {
    for (const char* ior : {"1.5", "3.9"}) {
        std::string glass = glass_sphere(0, 0, 0, 1.0);
        glass.replace(glass.find("ior = 1.5"), 9, std::string("ior = ") + ior);
        const Furnace f = furnace_pair(std::string(kCamera) + kFog + glass, 8, {"photons.gather=\"point_beam\""}, true);
        std::printf("point_beam, ior %s, 8 maps: split %.5f +- %.5f, mixed %.5f +- %.5f\n", ior, f.split.mean(), f.split.se(),
                    f.mixed.mean(), f.mixed.se());
        std::fflush(stdout);
    }
}
