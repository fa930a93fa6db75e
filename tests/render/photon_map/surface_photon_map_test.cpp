// The surface photon map (2D kNN estimate over pi r_k^2) in the renderer.
//
// The 2D estimators on synthetic uniform disc sets are tested in tests/photon/estimate/estimators_test.cpp
// (EstimatorsMonteCarlo.Disc2D); here the same order statistics are checked through the whole
// pipeline: photon tracer -> surface map -> PhotonMapIntegrator. Every statistical check uses the
// standard error over independent photon maps (fixed seeds).
#include <gtest/gtest.h>

#include <cstdio>

#include <nlohmann/json.hpp>

#include "photon/map/photon_map.h"
#include "photon/trace/photon_tracer.h"
#include "render/path/path_tracer.h"
#include "render/photon_map/photon_map_integrator.h"
#include "render/run/render_loop.h"
#include "render/run/run.h"
#include "scene/scene.h"
#include "support/render_statistics.h"

using namespace vpm;

namespace {

using test::Sample;
using test::image_mean;

PhotonTraceResult trace(const RunConfig& config, uint64_t seed, bool store_direct) {
    const Scene& scene = *config.scene;
    PhotonTraceSettings ts;
    ts.count = uint64_t(photon_map_settings(config).count);
    ts.seed = seed;
    ts.store_direct = store_direct;
    ts.store_surface = true;
    ts.progress = false;
    return trace_photons(scene, ts);
}

// A 10 x 10 Lambertian floor under a directional light, no medium: the surface photons are i.i.d.
// uniform on the floor, so the surface map's estimate is pure order statistics.
// Truth: L = reflectance / pi * E cos(theta).
constexpr double kFloorRho = 0.5, kIrradiance = 2.0;
const Vec3 kLightDir = Vec3(0.3, -1.0, 0.2).normalized();

RunConfig flat_floor(const std::vector<std::string>& overrides = {}) {
    const std::string text = R"(
[render]
width = 32
height = 32
spp = 1
integrator = "photon_map"
[camera]
position = [0, 4, 0.001]
look_at = [0, 0, 0]
fov = 20
[photons]
count = 200000
direct = "photon_map"
[[lights]]
type = "directional"
direction = [0.3, -1.0, 0.2]
irradiance = 2.0
[[shapes]]
type = "quad"
center = [0, 0, 0]
u = [5, 0, 0]
v = [0, 0, 5]
reflectance = 0.5
)";
    return RunConfig::build(parse_config(text, "flat_floor.toml", ".", overrides));
}

// A closed diffuse box [-1,1]^3 (reflectance 0.5) with a quad light under its ceiling, no medium;
// the camera inside looks at the back wall.
// light_table replaces the quad light (a point light keeps every hit on a grey wall: area lights are
// black geometry that absorbs the photons coming back to them).
RunConfig closed_box(bool with_medium, const std::vector<std::string>& overrides = {}, const std::string& light_table = "") {
    std::string text = R"(
[render]
width = 24
height = 24
spp = 1
integrator = "photon_map"
[camera]
position = [0, 0, 0.5]
look_at = [0, -0.1, -1]
fov = 40
[photons]
count = 150000
direct = "photon_map"
)" + (light_table.empty() ? std::string(R"([[lights]]
type = "quad"
center = [0, 0.99, 0]
u = [0.3, 0, 0]
v = [0, 0, 0.3]
radiance = 3.0
)") : light_table) + R"(
[[shapes]]
type = "box"
min = [-1, -1, -1]
max = [1, 1, 1]
reflectance = 0.5
)";
    if (with_medium)
        text += R"(
[[media]]
type = "homogeneous"
shape = "sphere"
center = [0, -0.3, 0]
radius = 0.5
sigma_t_scale = 2.0
albedo = [0.9, 0.7, 0.5]
g = 0.2
)";
    return RunConfig::build(parse_config(text, "closed_box.toml", ".", overrides));
}

}  // namespace

TEST(SurfacePhotonMap, FlatFloorClassicHighByOneOverKMinusOneCorrectedConsistent) {
    const RunConfig config = flat_floor();
    const Scene& scene = *config.scene;
    PhotonMapSettings ps = photon_map_settings(config);
    const double truth = kFloorRho / kPi * kIrradiance * (-kLightDir.y());
    const int repeats = 8;
    const int ks[] = {4, 8, 32};
    Sample classic[3], corrected[3], excess[3];
    for (int r = 0; r < repeats; ++r) {
        const PhotonTraceResult traced = trace(config, 300 + uint64_t(r), true);
        ASSERT_TRUE(traced.photons.empty());   // no medium: no volume photons
        const PhotonMap surface(traced.surface_photons);
        const PhotonMap volume;
        for (int i = 0; i < 3; ++i) {
            ps.k = ks[i];
            ps.estimator = Estimator::named("classic");
            const double c = image_mean(config, PhotonMapIntegrator(scene, ps, volume, &surface), 11 + uint64_t(r), 1);
            ps.estimator = Estimator::named("corrected");
            const double u = image_mean(config, PhotonMapIntegrator(scene, ps, volume, &surface), 11 + uint64_t(r), 1);
            classic[i].add(c / truth);
            corrected[i].add(u / truth);
            excess[i].add(c / u - 1.0);
        }
    }
    for (int i = 0; i < 3; ++i) {
        const double k = ks[i];
        std::printf("floor k = %2d: classic/truth %.4f +- %.4f (theory %.4f), corrected/truth %.4f +- %.4f, "
                    "paired excess %.4f +- %.4f (theory %.4f)\n", ks[i], classic[i].mean(), classic[i].se(),
                    k / (k - 1), corrected[i].mean(), corrected[i].se(), excess[i].mean(), excess[i].se(),
                    1.0 / (k - 1));
        EXPECT_NEAR(corrected[i].mean(), 1.0, 3.0 * corrected[i].se()) << "k = " << k;
        EXPECT_NEAR(classic[i].mean(), k / (k - 1), 3.0 * classic[i].se()) << "k = " << k;
        // Uniform i.i.d. photons: the ratio classic/corrected is k/(k-1) up to the photon
        // weights, which are all equal here (grey reflectance, one bounce).
        EXPECT_NEAR(excess[i].mean(), 1.0 / (k - 1), 3.0 * excess[i].se() + 1e-9) << "k = " << k;
        EXPECT_GT(classic[i].mean() - 1.0, 5.0 * classic[i].se()) << "k = " << k;
    }
}

TEST(SurfacePhotonMap, ClosedBoxWallAgreesWithPathTracer) {
    const RunConfig config = closed_box(false);
    const Scene& scene = *config.scene;
    PhotonMapSettings ps = photon_map_settings(config);
    // Reference: the path tracer over the same pixels, many samples (independent pixel seeds).
    const PathTracer pt(scene, ps.walk);
    Sample reference;
    for (int r = 0; r < 6; ++r) reference.add(image_mean(config, pt, 900 + uint64_t(r), 16));
    const int repeats = 8, k = 8;
    Sample classic, corrected;
    for (int r = 0; r < repeats; ++r) {
        const PhotonTraceResult traced = trace(config, 500 + uint64_t(r), true);
        const PhotonMap surface(traced.surface_photons);
        const PhotonMap volume;
        ps.k = k;
        ps.estimator = Estimator::named("classic");
        classic.add(image_mean(config, PhotonMapIntegrator(scene, ps, volume, &surface), 21 + uint64_t(r), 1));
        ps.estimator = Estimator::named("corrected");
        corrected.add(image_mean(config, PhotonMapIntegrator(scene, ps, volume, &surface), 21 + uint64_t(r), 1));
    }
    const double ref = reference.mean();
    std::printf("closed box wall: path %.5f +- %.5f, corrected %.5f +- %.5f, classic %.5f +- %.5f "
                "(classic/path %.4f, theory %.4f)\n", ref, reference.se(), corrected.mean(), corrected.se(),
                classic.mean(), classic.se(), classic.mean() / ref, double(k) / (k - 1));
    const double se_c = std::hypot(corrected.se(), reference.se());
    EXPECT_NEAR(corrected.mean(), ref, 3.0 * se_c);
    const double se_k = std::hypot(classic.se(), reference.se() * k / (k - 1.0));
    EXPECT_NEAR(classic.mean(), ref * k / (k - 1.0), 3.0 * se_k);
    EXPECT_GT(classic.mean() - ref, 5.0 * se_k);
}

TEST(SurfacePhotonMap, NeeConventionStoresOnlyScatteredPhotons) {
    // With store_direct false the surface map holds exactly the hits after the first event: in the
    // closed box without medium that is every hit but each path's first. Hits on the quad light
    // (opaque and black since area lights are geometry) absorb the photon and store nothing; a
    // photon's first hit is never its own light.
    const RunConfig config = closed_box(false, {"photons.count=20000"});
    const PhotonTraceResult all = trace(config, 7, true);
    const PhotonTraceResult indirect = trace(config, 7, false);
    EXPECT_EQ(all.surface_photons.size(), all.surface_hits - all.light_hits);
    EXPECT_GT(all.light_hits, 0u);
    EXPECT_EQ(indirect.surface_hits, all.surface_hits);   // same random walks
    EXPECT_EQ(indirect.surface_photons.size() + 20000u, all.surface_photons.size());
}

TEST(SurfacePhotonMap, ClosedBoxStoredPowerIsEmittedOverOneMinusReflectance) {
    // Grey reflectance rho: Russian roulette keeps the power and each hit survives with prob. rho,
    // so hits per path are geometric, mean 1/(1-rho), variance rho/(1-rho)^2; the stored power sums
    // to emitted * hits/N. A point light: every hit is on a grey wall.
    const RunConfig config = closed_box(false, {"photons.count=50000"}, "[[lights]]\ntype = 'point'\nposition = [0, 0.9, 0]\nintensity = 3\n");
    const PhotonTraceResult t = trace(config, 9, true);
    Rgb stored = Rgb::Zero();
    for (const auto& p : t.surface_photons) stored += p.power;
    const double rho = 0.5, n = 50000.0;
    const double expected = t.energy.emitted[1] / (1.0 - rho);
    const double se = t.energy.emitted[1] * std::sqrt(rho) / (1.0 - rho) / std::sqrt(n);
    EXPECT_NEAR(stored[1], expected, 4.0 * se);
    EXPECT_LT(t.energy.relative_imbalance(), 1e-9);
    EXPECT_EQ(t.energy.escaped[1], 0.0);   // closed box
}

TEST(SurfacePhotonMap, EnergyBalanceWithSurfacesAndMedia) {
    const RunConfig config = closed_box(true, {"photons.count=40000"});
    const PhotonTraceResult with = trace(config, 3, false);
    EXPECT_GT(with.collisions, 0u);
    EXPECT_GT(with.photons.size(), 0u);
    EXPECT_GT(with.surface_photons.size(), 0u);
    EXPECT_LT(with.energy.relative_imbalance(), 1e-9);
    for (int c = 0; c < 3; ++c) EXPECT_GT(with.energy.absorbed[c], 0.0);
    // Storing surface photons takes no power and no random numbers: the balance is identical.
    PhotonTraceSettings ts;
    ts.count = 40000;
    ts.seed = 3;
    ts.store_direct = false;
    ts.store_surface = false;
    ts.progress = false;
    const PhotonTraceResult without = trace_photons(*config.scene, ts);
    EXPECT_TRUE(without.surface_photons.empty());
    EXPECT_EQ(without.photons.size(), with.photons.size());
    for (int c = 0; c < 3; ++c) {
        EXPECT_EQ(without.energy.absorbed[c], with.energy.absorbed[c]);
        EXPECT_EQ(without.energy.escaped[c], with.energy.escaped[c]);
    }
}

TEST(SurfacePhotonMap, RunBuildsTheSurfaceMapOnlyWithoutFinalGather) {
    const std::vector<std::string> small = {"photons.count=20000", "render.width=8", "render.height=8"};
    RunOptions o;
    o.progress = false;
    const RunResult with = run(flat_floor(small), o);
    const auto& j = with.record.json();
    ASSERT_TRUE(j.contains("photons"));
    EXPECT_GT(j["photons"]["surface_stored"].get<uint64_t>(), 0u);
    EXPECT_EQ(j["photons"]["surface_estimate_cases"]["queries"].get<uint64_t>(), 64u);
    std::vector<std::string> gather = small;
    gather.push_back("photons.final_gather=true");   // no media either: no photon pass at all
    const RunResult without = run(flat_floor(gather), o);
    const auto& p = without.record.json()["photons"];
    EXPECT_FALSE(p.contains("emitted"));
    EXPECT_FALSE(p.contains("surface_stored"));
    EXPECT_FALSE(p.contains("surface_estimate_cases"));
}
