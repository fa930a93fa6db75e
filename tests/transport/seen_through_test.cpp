// transport/seen_through.h: the exact transmittance of a camera segment, against the closed form of
// a homogeneous sphere and against the mean of the scene's unbiased ratio-tracking estimates
// through the blob grid overlapping that sphere; and the sky seen through them is that
// transmittance times the sky's radiance, with no random numbers drawn.
#include <gtest/gtest.h>

#include <cmath>

#include "config/params.h"
#include "core/math.h"
#include "transport/seen_through.h"
#include "transport/march_points.h"
#include "scene/scene.h"
#include "support/sample_statistics.h"
#include "support/scene_from_config.h"

using namespace vpm;

namespace {

std::unique_ptr<Scene> scene_from(const std::string& text) {
    return test::scene_from_config("[camera]\nposition = [0, 0, 4]\nlook_at = [0, 0, 0]\n" + text, 8, 8, "seen.toml");
}

const std::string kSky = "[[lights]]\ntype = 'environment'\nradiance = 1.5\n";
const std::string kSphere =
    "[[media]]\ntype = 'homogeneous'\nshape = 'sphere'\ncenter = [0.3, 0, 0]\nradius = 0.6\nsigma_t_scale = 2\nalbedo = 0.8\n";
const std::string kBlob = "[[media]]\ntype = 'grid'\nfile = '" VPM_SOURCE_DIR
                          "/media/blob.vdb'\ntransform = { scale = 1.3333333333333333 }\nsigma_t_scale = 3\nalbedo = 0.9\n";

}  // namespace

TEST(SeenThrough, HomogeneousSphereIsTheClosedForm) {
    const auto scene = scene_from(kSky + kSphere);
    OpticalDepthProfile profile;
    // Through the sphere's centre: chord 1.2, optical depth 2.4.
    const Ray ray{Vec3(0.3, 0, 4), Vec3(0, 0, -1)};
    EXPECT_NEAR(exact_transmittance(*scene, ray, kInfinity, profile), std::exp(-2.4), 1e-12);
    SurfaceHit none;
    uint64_t rays = 0;
    const Rgb sky = seen_through(*scene, ray, false, none, EmissionWeighting::camera(), profile, rays);
    EXPECT_NEAR(sky[1], 1.5 * std::exp(-2.4), 1e-12);
    EXPECT_EQ(rays, 1u);
    // Under a point light there is nothing to weigh and nothing is counted.
    const auto dark = scene_from("[[lights]]\ntype = 'point'\nposition = [0, 3, 0]\nintensity = 1\n" + kSphere);
    EXPECT_EQ(seen_through(*dark, ray, false, none, EmissionWeighting::camera(), profile, rays)[1], 0.0);
    EXPECT_EQ(rays, 1u);
    // Up to t = 4.1 the ray has crossed 0.4 of the chord (it enters at t = 3.4).
    EXPECT_NEAR(exact_transmittance(*scene, ray, 4.1 - 0.3, profile), std::exp(-2.0 * 0.4), 1e-12);
}

TEST(SeenThrough, GridAndSphereMatchTheMeanOfRatioTracking) {
    const auto scene = scene_from(kSky + kBlob + kSphere);
    OpticalDepthProfile profile;
    Rng rng(5, 6);
    const Ray rays[] = {{Vec3(0, 0, 4), Vec3(0, 0, -1)},
                        {Vec3(0.2, 0.3, 4), Vec3(-0.1, -0.05, -1).normalized()},
                        {Vec3(-3, 0.4, 0.1), Vec3(1, -0.1, 0).normalized()}};
    for (const Ray& ray : rays) {
        const double exact = exact_transmittance(*scene, ray, kInfinity, profile);
        test::Sample tracked;
        for (int i = 0; i < 40000; ++i) tracked.add(scene->transmittance(ray, kInfinity, rng));
        std::printf("exact %.6f, ratio tracking %.6f +- %.6f\n", exact, tracked.mean(), tracked.se());
        EXPECT_GT(exact, 0.0);
        EXPECT_LT(exact, 0.99);   // the ray really crosses a medium
        EXPECT_NEAR(exact, tracked.mean(), 4.0 * tracked.se() + 1e-9);
    }
}

TEST(SeenThrough, TheMarchsDepthIsTheExactTransmittancesToTheBit) {
    // The march gather weighs the light behind a segment by exp(-depth) from its own profiles
    // (for_each_march_point's depth; render/photon_map/photon_map_integrator.cpp): the same sum in the same
    // order as exact_transmittance, an absorbing medium (albedo 0, no march points) included.
    const std::string absorbing = "[[media]]\ntype = 'homogeneous'\nshape = 'sphere'\ncenter = [-0.3, 0.1, 0]\nradius = 0.5\n"
                                  "sigma_t_scale = 1.5\nalbedo = 0\n";
    const auto scene = scene_from(kSky + kBlob + kSphere + absorbing);
    OpticalDepthProfile profile;
    Rng rng(5, 7);
    const Ray rays[] = {{Vec3(0, 0, 4), Vec3(0, 0, -1)},
                        {Vec3(0.2, 0.3, 4), Vec3(-0.1, -0.05, -1).normalized()},
                        {Vec3(-3, 0.1, 0.05), Vec3(1, -0.02, 0).normalized()}};
    for (const Ray& ray : rays)
        for (const double t_end : {kInfinity, 3.9}) {
            double depth = 0.0;
            uint64_t tracked = 0;
            int points = 0;
            for_each_march_point(*scene, ray, t_end, 4, MarchCount::mass, rng, 1, tracked,
                                 [&](const Medium&, double, double, MarchMass) { ++points; }, &depth);
            const double exact = exact_transmittance(*scene, ray, t_end, profile);
            EXPECT_LT(exact, 0.95);
            EXPECT_GT(points, 0);
            EXPECT_EQ(std::exp(-depth), exact);
            SurfaceHit none;
            uint64_t r1 = 0, r2 = 0;
            const Rgb a = seen_through(*scene, ray, false, none, EmissionWeighting::camera(), profile, r1);
            double whole = 0.0;
            for_each_march_point(*scene, ray, kInfinity, 4, MarchCount::mass, rng, 1, tracked,
                                 [](const Medium&, double, double, MarchMass) {}, &whole);
            const Rgb b = seen_through_depth(*scene, ray, false, none, EmissionWeighting::camera(), whole, r2);
            EXPECT_EQ(a[1], b[1]);
            EXPECT_EQ(r1, r2);
        }
}
