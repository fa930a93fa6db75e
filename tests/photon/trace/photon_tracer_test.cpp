// The photon pass: energy balance per run, determinism across thread counts, and the
// storage convention for direct = "nee".
#include <gtest/gtest.h>

#include <tbb/task_arena.h>

#include <cmath>
#include <iostream>

#include "photon/trace/photon_tracer.h"
#include "render/run/run_config.h"

#include "support/sample_statistics.h"

using namespace vpm;

namespace {

std::unique_ptr<Scene> scene_with_medium(const std::string& medium, const std::string& extra = "") {
    const std::string text = R"(
[camera]
position = [0, 0, 5]
look_at = [0, 0, 0]
[[lights]]
type = "spot"
position = [0, 3, 0]
look_at = [0, 0, 0]
intensity = [4, 3, 2]
cone_angle = 40
[[lights]]
type = "environment"
radiance = 0.1
[[media]]
)" + medium + extra;
    return RunConfig::build(parse_config(text, "photons.toml", VPM_SOURCE_DIR "/configs")).scene;
}

const std::string kHomogeneous = "type = 'homogeneous'\nshape = 'sphere'\nradius = 1\nsigma_t_scale = 3\ng = 0.4\n";
const std::string kGrid = "type = 'grid'\nfile = '../media/plume.vdb'\nsigma_t_scale = 8\ng = 0.6\n";

}  // namespace

TEST(PhotonTracer, EnergyBalancesInHomogeneousAndGridMedia) {
    for (const std::string& medium : {kHomogeneous, kGrid}) {
        for (double albedo : {0.0, 0.5, 1.0}) {
            auto scene = scene_with_medium(medium, "albedo = " + std::to_string(albedo) + "\n");
            PhotonTraceSettings s;
            s.count = 20000;
            s.max_bounces = 20;   // the cap truncates some albedo-1 paths: they must be accounted for
            s.progress = false;
            const PhotonTraceResult r = trace_photons(*scene, s);
            EXPECT_LT(r.energy.relative_imbalance(), 1e-6) << medium << " albedo " << albedo;
            // The emitted total is the lights' power, up to Monte Carlo noise of the light choice.
            EXPECT_NEAR(r.energy.emitted[0] / scene->total_light_power()[0], 1.0, 0.05);
            if (albedo == 0.0) {
                EXPECT_EQ(r.energy.truncated.maxCoeff(), 0.0);
            }
            if (albedo == 1.0) {
                EXPECT_NEAR(r.energy.absorbed.maxCoeff(), 0.0, 1e-9 * r.energy.emitted.maxCoeff());
            }
            EXPECT_GT(r.photons.size(), 0u);
        }
    }
}

TEST(PhotonTracer, SamePhotonsForAnyThreadCount) {
    auto scene = scene_with_medium(kHomogeneous, "albedo = 0.8\n");
    PhotonTraceSettings s;
    s.count = 30000;
    s.progress = false;
    PhotonTraceResult one, two;
    tbb::task_arena(1).execute([&] { one = trace_photons(*scene, s); });
    tbb::task_arena(2).execute([&] { two = trace_photons(*scene, s); });
    ASSERT_EQ(one.photons.size(), two.photons.size());
    for (size_t i = 0; i < one.photons.size(); ++i) {
        ASSERT_EQ(one.photons[i].position, two.photons[i].position) << i;
        ASSERT_TRUE((one.photons[i].power == two.photons[i].power).all()) << i;
    }
    EXPECT_TRUE((one.energy.escaped == two.energy.escaped).all());
}

TEST(PhotonTracer, NeeModeStoresOnlyScatteredLight) {
    auto scene = scene_with_medium(kHomogeneous, "albedo = 0.0\n");
    PhotonTraceSettings s;
    s.count = 5000;
    s.progress = false;
    s.store_direct = false;
    // Albedo 0: every photon dies at its first collision, which NEE covers: nothing is stored.
    EXPECT_EQ(trace_photons(*scene, s).photons.size(), 0u);
    s.store_direct = true;
    const auto all = trace_photons(*scene, s);
    EXPECT_EQ(all.photons.size(), all.collisions);
}

TEST(PhotonTracer, EnvironmentMapEnergyBalancesAndEmitsItsPower) {
    // The sun-and-sky map of configs/plume_sky.toml with a point light beside it: every photon's
    // power is emitted, absorbed, escaped or truncated, and the emitted total is the lights' power
    // within the standard error of the map's photon weights (measured from the light itself).
    for (const std::string& medium : {kHomogeneous, kGrid}) {
        const std::string text = R"(
[camera]
position = [0, 0, 5]
look_at = [0, 0, 0]
[[lights]]
type = "environment"
file = "../media/sky.exr"
rotate_y = 40
scale = [1.5, 1, 0.8]
[[lights]]
type = "point"
position = [0, 3, 0]
intensity = 2
[[media]]
)" + medium + "albedo = 0.7\n";
        auto scene = RunConfig::build(parse_config(text, "sky_photons.toml", VPM_SOURCE_DIR "/configs")).scene;
        const Light& sky = *scene->lights[0];
        // Relative standard deviation of one map photon's power (luminance), by sampling the light.
        Rng rng(77, 1);
        test::Sample one;
        for (int i = 0; i < 20000; ++i) one.add(luminance(sky.sample_emission(rng).power) / luminance(sky.power()));
        const double rel_sd = one.se() * std::sqrt(double(one.n));
        PhotonTraceSettings s;
        s.count = 40000;
        s.progress = false;
        const PhotonTraceResult r = trace_photons(*scene, s);
        EXPECT_LT(r.energy.relative_imbalance(), 1e-6) << medium;
        // Photons go to the lights by power; the point light's are exact, the map's mean carries
        // rel_sd / sqrt(its photon count), which bounds the total's relative error from above.
        const double tol = 4.0 * rel_sd / std::sqrt(double(s.count) * 0.5);
        std::cout << "emitted / power " << luminance(r.energy.emitted) / luminance(scene->total_light_power())
                  << " (tolerance " << tol << "), imbalance " << r.energy.relative_imbalance() << "\n";
        EXPECT_NEAR(luminance(r.energy.emitted) / luminance(scene->total_light_power()), 1.0, tol) << medium;
        EXPECT_LT(tol, 0.05);
        EXPECT_GT(r.photons.size(), 0u);
    }
}

TEST(PhotonTracer, EnergyBalancesWithAreaLights) {
    // A sphere light and a one-sided quad light (facing up, u x v = +y) beside the spot, around the homogeneous sphere. The
    // lights are picked by luminance power and every light's photons carry its power / its pick
    // probability, so without lights at infinity each photon carries luminance total power / N: the
    // emitted luminance is the scene's exactly. Area lights are black: photons that come back to them are absorbed.
    const std::string text = R"(
[camera]
position = [0, 0, 5]
look_at = [0, 0, 0]
[[lights]]
type = "spot"
position = [0, 3, 0]
look_at = [0, 0, 0]
intensity = [4, 3, 2]
cone_angle = 40
[[lights]]
type = "sphere"
center = [1.8, 0.5, 0]
radius = 0.4
radiance = [1, 2, 3]
[[lights]]
type = "quad"
center = [0, -1.5, 0]
u = [0.5, 0, 0]
v = [0, 0, -0.5]
radiance = 2
[[media]]
)" + kHomogeneous;
    for (double albedo : {0.0, 0.5, 1.0}) {
        auto scene = RunConfig::build(parse_config(text + "albedo = " + std::to_string(albedo) + "\n", "area.toml", ".")).scene;
        ASSERT_EQ(scene->area_lights().size(), 2u);
        PhotonTraceSettings s;
        s.count = 80000;
        s.max_bounces = 20;
        s.progress = false;
        const PhotonTraceResult r = trace_photons(*scene, s);
        EXPECT_LT(r.energy.relative_imbalance(), 1e-6) << "albedo " << albedo;
        const double lum = luminance(scene->total_light_power());
        // The spot and the sphere light beside the medium are guided (scene/emission_guides.h): their
        // photons' powers vary, by up to 2x about their mean, so the total is exact only in expectation
        // (0.06-0.6% off at 80000 photons over the three albedos, about 0.4% one standard error); the
        // quad's is exact.
        ASSERT_EQ(scene->prepare_photon_emission().size(), 2u);
        EXPECT_NEAR(luminance(r.energy.emitted), lum, 0.02 * lum);
        // Each light emits its power share of the photons (binomial standard error).
        const double total = lum;
        for (size_t l = 0; l < scene->lights.size(); ++l) {
            const double p = luminance(scene->lights[l]->power()) / total;
            const double n = double(s.count);
            EXPECT_NEAR(double(r.per_light[l].emitted), n * p, 4.0 * std::sqrt(n * p * (1.0 - p)) + 1.0) << "light " << l;
            EXPECT_GT(r.per_light[l].landed, 0u) << "light " << l;
        }
        if (albedo == 1.0) {
            EXPECT_GT(r.light_hits, 0u);
            EXPECT_GT(r.energy.absorbed.maxCoeff(), 0.0);   // only the black lights absorb
        }
        EXPECT_GT(r.photons.size(), 0u);
    }
}

TEST(PhotonTracer, ThinnedStorageKeepsTheStoredPowerUnbiased) {
    // photons.store_probability = p keeps each volume collision with probability p and power / p:
    // per emitted photon, the stored power has the same mean as without thinning (8 independent
    // maps each, 4 combined standard errors), and about p of the photons are kept.
    auto scene = scene_with_medium(kHomogeneous, "albedo = 0.95\n");
    auto stored_power = [&](double p, uint64_t seed, double& count) {
        PhotonTraceSettings s;
        s.count = 20000;
        s.seed = seed;
        s.progress = false;
        s.store_probability = p;
        const PhotonTraceResult r = trace_photons(*scene, s);
        double sum = 0.0;
        for (const PhotonInput& ph : r.photons) sum += ph.power[1];
        count = double(r.photons.size()) / double(r.collisions);
        return sum / double(s.count);
    };
    test::Sample full, thinned, kept;
    double c = 0.0;
    for (uint64_t seed = 1; seed <= 8; ++seed) {
        full.add(stored_power(1.0, seed, c));
        EXPECT_DOUBLE_EQ(c, 1.0);
        thinned.add(stored_power(0.25, 100 + seed, c));
        kept.add(c);
    }
    EXPECT_NEAR(thinned.mean(), full.mean(), 4.0 * std::hypot(full.se(), thinned.se()));
    EXPECT_GT(thinned.se(), full.se());   // thinning trades photons for variance
    EXPECT_NEAR(kept.mean(), 0.25, 0.01);
}

TEST(PhotonTracer, ForcedCollisionsKeepTheStoredPowerAndItsDistribution) {
    // photons.forced_collisions (photon/trace/forced_collision.h): in a thin medium every segment collides
    // with power times 1 - exp(-tau). Per emitted photon the stored power, and its first moments in
    // x and y (where it lands), have the analog walk's means (8 independent maps each, 4 combined
    // standard errors), the energy balances, and the thin sphere (optical depth 0.6 across) and the
    // thin plume store several times more photons.
    for (const std::string& medium :
         {std::string("type = 'homogeneous'\nshape = 'sphere'\nradius = 1\nsigma_t_scale = 0.3\ng = 0.4\n"),
          std::string("type = 'grid'\nfile = '../media/plume.vdb'\nsigma_t_scale = 0.5\ng = 0.6\n")}) {
        auto scene = scene_with_medium(medium, "albedo = 0.9\n");
        test::Sample analog[3], forced[3];
        double stored_analog = 0.0, stored_forced = 0.0;
        for (uint64_t seed = 1; seed <= 8; ++seed) {
            for (const bool force : {false, true}) {
                PhotonTraceSettings s;
                s.count = 20000;
                s.seed = seed + (force ? 100 : 0);
                s.progress = false;
                s.forced_collisions = force;
                const PhotonTraceResult r = trace_photons(*scene, s);
                EXPECT_LT(r.energy.relative_imbalance(), 1e-9) << medium;
                double m[3] = {0.0, 0.0, 0.0};
                for (const PhotonInput& ph : r.photons) {
                    m[0] += ph.power[1];
                    m[1] += ph.power[1] * ph.position.x();
                    m[2] += ph.power[1] * ph.position.y();
                }
                for (int i = 0; i < 3; ++i) (force ? forced : analog)[i].add(m[i] / double(s.count));
                (force ? stored_forced : stored_analog) += double(r.photons.size());
            }
        }
        for (int i = 0; i < 3; ++i)
            EXPECT_NEAR(forced[i].mean(), analog[i].mean(), 4.0 * std::hypot(forced[i].se(), analog[i].se()))
                << medium << " moment " << i;
        EXPECT_GT(stored_forced, 2.0 * stored_analog) << medium;
    }
}
