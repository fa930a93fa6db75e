// The photon-map renderer on a scene whose photon density is uniform: the inside of a thick,
// non-absorbing sphere under a constant environment (a volume furnace). There the radiance is
// L_env everywhere, the collision density is uniform, and the estimator's overestimation shows
// unmixed: corrected ~ L_env, classic k/(k-1) L_env in every estimate, each checked within 3
// standard errors of the mean over independent photon maps (the image mixes in the sky seen
// through the sphere: support/furnace.h).
#include <gtest/gtest.h>

#include <cstdio>

#include "photon/map/photon_map.h"
#include "photon/trace/photon_tracer.h"
#include "render/path/path_tracer.h"
#include "render/photon_map/photon_map_integrator.h"
#include "render/run/render_loop.h"
#include "render/run/run_config.h"
#include "support/furnace.h"
#include "support/render_statistics.h"

using namespace vpm;

namespace {


RunConfig furnace() {
    return RunConfig::load(VPM_SOURCE_DIR "/configs/uniform_furnace.toml",
                           {"render.width=24", "render.height=24", "render.spp=1", "photons.count=100000"});
}

// Mean image value (green channel) at the config's spp.
double image_mean(const RunConfig& config, const PhotonMapSettings& settings, const PhotonMap& map, uint64_t seed) {
    return test::image_mean(config, PhotonMapIntegrator(*config.scene, settings, map), seed, config.render.spp);
}

using test::Sample;

}  // namespace

TEST(PhotonMapRender, ClassicOverestimatesByKOverKMinusOneCorrectedDoesNot) {
    // The photon density near the camera fluctuates between photon maps (long random walks
    // leave chains of collisions), so the mean image value varies ~5% per map: the absolute
    // checks use the standard error over maps, and the classic/corrected ratio is checked paired
    // (same map, same camera rays), which is far more precise.
    const RunConfig config = furnace();
    PhotonMapSettings ps = photon_map_settings(config);
    const double kEnv = config.scene->escaped_radiance(Vec3::UnitZ())[1];   // the furnace's radiance everywhere
    const double estimated = test::furnace_estimated_share(config);
    // 20 maps: the map-to-map spread is large here (0.48 - 0.54 for single maps); with 12 maps the
    // stream of the silhouette emission (issue 12) put seeds 1000.. at -3.0 SE (seeds 3000..: +0.8).
    const int repeats = 20;
    const int ks[] = {4, 8, 16};
    Sample classic[3], corrected[3], excess[3];
    for (int r = 0; r < repeats; ++r) {
        PhotonTraceSettings ts;
        ts.count = uint64_t(ps.count);
        ts.seed = 1000 + uint64_t(r);
        ts.progress = false;
        const PhotonMap map(trace_photons(*config.scene, ts).photons);
        for (int i = 0; i < 3; ++i) {
            ps.k = ks[i];
            ps.estimator = Estimator::named("classic");
            const double c = image_mean(config, ps, map, 77 + uint64_t(r));
            ps.estimator = Estimator::named("corrected");
            const double u = image_mean(config, ps, map, 77 + uint64_t(r));
            classic[i].add(c);
            corrected[i].add(u);
            excess[i].add(c / u - 1.0);
        }
    }
    for (int i = 0; i < 3; ++i) {
        const double k = ks[i];
        // Each classic estimate is k/(k-1) high (order statistics of the k-th neighbour; exact for any
        // point process whose photon weights do not depend on their rank, walks included); the image
        // holds it on its estimated share only.
        const double excess_theory = estimated / (k - 1);
        EXPECT_NEAR(corrected[i].mean(), kEnv, 3.0 * corrected[i].se()) << "k = " << k;
        EXPECT_NEAR(classic[i].mean(), kEnv * (1.0 + excess_theory), 3.0 * classic[i].se()) << "k = " << k;
        EXPECT_NEAR(excess[i].mean(), excess_theory, 3.0 * excess[i].se()) << "k = " << k;
        std::printf("k = %2d: classic %.4f +- %.4f (theory %.4f), corrected %.4f +- %.4f (theory %.4f), "
                    "paired excess %.4f +- %.4f (theory %.4f)\n", ks[i], classic[i].mean(), classic[i].se(),
                    kEnv * (1.0 + excess_theory), corrected[i].mean(), corrected[i].se(), kEnv, excess[i].mean(),
                    excess[i].se(), excess_theory);
        // Decisive: the paired excess is many standard errors away from zero bias.
        EXPECT_GT(excess[i].mean(), 8.0 * excess[i].se()) << "k = " << k;
    }
}

TEST(PhotonMapRender, PathTracerAgreesWithTheFurnace) {
    const RunConfig config = furnace();
    const double kEnv = config.scene->escaped_radiance(Vec3::UnitZ())[1];   // the furnace's radiance everywhere
    const PathTracer pt(*config.scene);
    double sum = 0, sum2 = 0;
    const int n = 20000;
    for (int i = 0; i < n; ++i) {
        Rng rng(5, uint64_t(i));
        const double l = pt.radiance(Ray{Vec3::Zero(), Vec3(0.1, 0.2, -1).normalized()}, rng)[1];
        sum += l;
        sum2 += l * l;
    }
    const double mean = sum / n, se = std::sqrt((sum2 / n - mean * mean) / n);
    EXPECT_NEAR(mean, kEnv, 3.0 * se);
}

TEST(PhotonMapRender, BallExtinctionEqualsPointInsideAHomogeneousMedium) {
    // A kNN ball inside the sphere, where sigma_t is constant, gives the two normalisations the same
    // value. The few collisions within a kNN radius of the sphere's surface (radius 6) have balls
    // reaching out of it, where "ball" now takes the exact lens volume (Medium::ball_integral; the
    // 32-point rule before issue 20 happened to put no point outside): 5e-6 relative here.
    const RunConfig config = furnace();
    PhotonMapSettings ps = photon_map_settings(config);
    PhotonTraceSettings ts;
    ts.count = 50000;
    ts.progress = false;
    const PhotonMap map(trace_photons(*config.scene, ts).photons);
    ps.extinction = ExtinctionNormalisation::point;
    const double point = image_mean(config, ps, map, 5);
    ps.extinction = ExtinctionNormalisation::ball;
    const double ball = image_mean(config, ps, map, 5);
    EXPECT_NEAR(ball, point, 1e-4 * point);
    EXPECT_GT(point, 0.0);
}
