// render/seen_through.h: the exact transmittance of a camera segment, against the closed form of
// a homogeneous sphere and against the mean of the scene's unbiased ratio-tracking estimates
// through the blob grid overlapping that sphere; and the sky seen through them is that
// transmittance times the sky's radiance, with no random numbers drawn.
#include <gtest/gtest.h>

#include <cmath>

#include "config/params.h"
#include "core/math.h"
#include "render/seen_through.h"
#include "scene/scene.h"
#include "../support/sample_statistics.h"
#include "../support/scene_from_config.h"

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
