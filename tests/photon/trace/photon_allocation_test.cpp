// Issue 12, "photons where they can matter": per-light photon shares, per-light counts, and the
// case that was 3000x too dark (configs/inside_large_sphere.toml: camera and point light inside a
// sphere of radius 1000 under a sky light that takes nearly all of the power).
#include <gtest/gtest.h>

#include <sstream>

#include <nlohmann/json.hpp>

#include "photon/trace/photon_allocation.h"
#include "photon/map/photon_map.h"
#include "photon/trace/photon_tracer.h"
#include "render/path/path_tracer.h"
#include "render/photon_map/photon_map_integrator.h"
#include "render/run/run.h"
#include "render/run/run_config.h"
#include "support/render_statistics.h"

using namespace vpm;

namespace {

RunConfig inside_sphere(const std::string& allocation) {
    return RunConfig::load(VPM_SOURCE_DIR "/configs/inside_large_sphere.toml",
                           {"render.width=12", "render.height=12", "photons.count=40000", "photons.allocation=" + allocation});
}

struct Comparison {
    test::Sample pm, pt;
    double z() const { return (pm.mean() - pt.mean()) / std::sqrt(pm.se() * pm.se() + pt.se() * pt.se()); }
};

Comparison compare(const RunConfig& config, const PhotonMapSettings& ps, int repeats) {
    Comparison c;
    const Scene& scene = *config.scene;
    for (int r = 0; r < repeats; ++r) {
        PhotonTraceSettings ts;
        ts.count = uint64_t(ps.count);
        ts.seed = 70 + uint64_t(r);
        ts.progress = false;
        ts.store_direct = false;
        const LightAllocation a = ps.allocation == PhotonAllocationRule::importance ? importance_allocation(scene, ts)
                                                                                   : power_allocation(scene);
        ts.light_weights = a.weights;
        const PhotonMap map(trace_photons(scene, ts).photons);
        c.pm.add(test::image_mean(config, PhotonMapIntegrator(scene, ps, map), 20 + uint64_t(r), 2));
        c.pt.add(test::image_mean(config, PathTracer(scene, ps.walk), 300 + uint64_t(r), 16));
    }
    return c;
}

}  // namespace

TEST(PhotonAllocation, WeightsAreUnbiasedAndCountedPerLight) {
    // Any light weights: the emitted power is the lights' power in expectation, and each light
    // emits its share of the photons.
    const RunConfig config = RunConfig::load(VPM_SOURCE_DIR "/configs/homogeneous.toml", {});
    const Scene* scene = config.scene.get();
    PhotonTraceSettings ts;
    ts.count = 200000;
    ts.progress = false;
    ts.light_weights = {0.2, 0.8};
    const PhotonTraceResult r = trace_photons(*scene, ts);
    ASSERT_EQ(r.per_light.size(), 2u);
    EXPECT_EQ(r.per_light[0].emitted + r.per_light[1].emitted, ts.count);
    const double n = double(ts.count), share = double(r.per_light[0].emitted) / n;
    EXPECT_NEAR(share, 0.2, 3.0 * std::sqrt(0.2 * 0.8 / n));
    EXPECT_EQ(r.per_light[0].stored + r.per_light[1].stored, r.photons.size());
    EXPECT_LE(r.per_light[0].landed, r.per_light[0].emitted);
    // Emitted power per light is exact per photon (power / pick probability): the total is the
    // scene's power up to the binomial noise of the picks.
    const double total = scene->total_light_power()[1];
    const double p0 = scene->lights[0]->power()[1], p1 = scene->lights[1]->power()[1];
    const double expected_emitted = double(r.per_light[0].emitted) * p0 / (0.2 * n) +
                                    double(r.per_light[1].emitted) * p1 / (0.8 * n);
    EXPECT_LT(std::abs(r.energy.emitted[1] - expected_emitted), 1e-6 * total);
    EXPECT_LT(r.energy.relative_imbalance(), 1e-9);
    EXPECT_THROW(([&] { PhotonTraceSettings bad = ts; bad.light_weights = {1.0, 0.0}; trace_photons(*scene, bad); })(),
                 Error);
}

TEST(PhotonAllocation, ImportanceGivesThePointLightItsPhotonsInsideALargeSphere) {
    const RunConfig config = inside_sphere("importance");
    PhotonTraceSettings ts;
    ts.progress = false;
    ts.store_direct = false;
    const LightAllocation a = importance_allocation(*config.scene, ts);
    const LightAllocation p = power_allocation(*config.scene);
    std::printf("importance: %s\npower: %s\n", a.to_string().c_str(), p.to_string().c_str());
    EXPECT_TRUE(a.from_pilot);
    EXPECT_LT(p.weights[0], 1e-3);   // by power the point light gets almost nothing
    EXPECT_GT(a.weights[0], 0.85);   // by importance nearly all (sky keeps its 10% power mix)
    EXPECT_GE(a.weights[1], kPowerMix * p.power_share[1] - 1e-12);
}

TEST(PhotonAllocation, InsideALargeSphereThePhotonMapAgreesWithThePathTracer) {
    const RunConfig config = inside_sphere("importance");
    const Comparison c = compare(config, photon_map_settings(config), 6);
    std::printf("importance: PM %.6f +- %.6f, PT %.6f +- %.6f, z %.2f\n", c.pm.mean(), c.pm.se(), c.pt.mean(),
                c.pt.se(), c.z());
    EXPECT_LT(std::abs(c.z()), 3.0);
}

TEST(PhotonAllocation, InsideALargeSphereByPowerTheCheckFails) {
    // Before issue 12 photons were shared by power and the kNN radius was not bounded: the same
    // comparison fails by far. (With the radius bound alone, camera paths continue where the point
    // light's few photons leave the balls empty, which hides most of the error at a higher cost.)
    const RunConfig config = inside_sphere("power");
    PhotonMapSettings ps = photon_map_settings(config);
    ps.max_radius_mfp = 0.0;
    const Comparison c = compare(config, ps, 6);
    std::printf("power: PM %.6f +- %.6f, PT %.6f +- %.6f\n", c.pm.mean(), c.pm.se(), c.pt.mean(), c.pt.se());
    EXPECT_LT(c.pm.mean(), 0.5 * c.pt.mean());
}

TEST(PhotonAllocation, RunReportsStoredPerEmittedPerLightAndWarnsAboutWastedLights) {
    // A spot light aimed away from the only medium: its photons reach nothing.
    const std::string text = R"(
[render]
width = 4
height = 4
spp = 1
integrator = "photon_map"
[camera]
position = [0, 0, 5]
look_at = [0, 0, 0]
[photons]
count = 20000
[[lights]]
type = "spot"
position = [0, 3, 0]
look_at = [0, 10, 0]
intensity = 5
cone_angle = 10
[[lights]]
type = "point"
position = [0, 0.5, 0]
intensity = 1
[[media]]
type = "homogeneous"
shape = "sphere"
radius = 1
sigma_t_scale = 2
albedo = 0.9
)";
    const RunConfig config = RunConfig::build(parse_config(text, "wasted.toml", "."));
    std::ostringstream log;
    RunOptions o;
    o.progress = false;
    o.log = &log;
    const RunResult r = run(config, o);
    const auto& j = r.record.json();
    ASSERT_TRUE(j["photons"].contains("stored_per_emitted"));
    ASSERT_EQ(j["photons"]["lights"].size(), 2u);
    // The spot points away from the sphere: its cone and the cone around the scene do not meet, so it
    // emits no photons at all (before emission toward the scene it emitted and wasted 2/3 of them).
    EXPECT_TRUE(j["photons"]["lights"][0]["reaches_nothing"].get<bool>());
    EXPECT_EQ(j["photons"]["lights"][0]["emitted"].get<uint64_t>(), 0u);
    EXPECT_EQ(j["photons"]["lights"][0]["landed"].get<uint64_t>(), 0u);
    EXPECT_FALSE(j["photons"]["lights"][1]["reaches_nothing"].get<bool>());
    EXPECT_FALSE(j["photons"]["lights"][1]["wasted"].get<bool>());
    EXPECT_NE(log.str().find("warning: light 0"), std::string::npos) << log.str();
    EXPECT_NE(log.str().find("stored per"), std::string::npos) << log.str();
}
