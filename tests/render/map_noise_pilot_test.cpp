// The auto pilot's per-sample variance V_camera (render/map_noise_pilot.h) where the camera noise
// lives in a thin band of the image that the 8 x 8 pilot pixels miss: the lit rim of a sphere held
// 75% of the march's noise in 1% of the pixels there, and the pilot read 1/7 of it (BENCHMARKS.md
// section 23). Synthetic hooks: every pixel returns 1 except one column, whose samples are uniform.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/rng.h"
#include "photon/photon_map.h"
#include "render/map_noise_pilot.h"
#include "scene/camera.h"
#include "../support/synthetic_pilot_hooks.h"

using namespace vpm;

TEST(MapNoisePilot, CameraVarianceSeesABandTheCoarsePixelsMiss) {
    constexpr int kSide = 32;
    const Camera camera(Vec3(0, 0, 4), Vec3(0, 0, 0), Vec3(0, 1, 0), 40.0, kSide, kSide);
    // The pixel column a camera ray came from (its x in the image plane, either way round).
    const double x_left = camera.generate_ray(0.5, 16.0).dir.x();
    auto column = [&](const Ray& r) {
        const double t = r.dir.x() / -r.dir.z() / std::tan(20.0 * kPi / 180.0);   // -1 .. 1 across the image
        const int c = std::clamp(int((t + 1.0) * 0.5 * kSide), 0, kSide - 1);
        return x_left < 0.0 ? c : kSide - 1 - c;
    };
    // Column 27: no 8 x 8 pilot pixel (columns 2, 6, ..., 30) lies in it. Uniform samples of
    // variance 1 / 12 there, 1 elsewhere: the image's mean per-pixel variance is (1 / 12) / 32.
    constexpr int kBand = 27;
    MapNoisePilotHooks hooks = test::synthetic_pilot_hooks([&](const Ray& r, Rng& rng) { return Rgb::Constant(column(r) == kBand ? 0.5 + rng.uniform() : 1.0); });
    const PhotonMap map;
    const auto m = measure_gathers(camera, map, {{"collision", true}}, hooks, 5, 0);
    ASSERT_EQ(m.size(), 1u);
    const double image = (1.0 / 12.0) / kSide;
    // The 16 x 16 centres (odd columns) hold one pixel in 16 of the band, 2 samples each; weighted
    // with the 64 coarse pixels (variance 0) that is 0.8 of the image's figure, within +-30% (one SE
    // of 16 two-sample variances of a uniform): the 8 x 8 centres alone read exactly 0.
    EXPECT_GT(m[0].v_camera, 0.35 * image);
    EXPECT_LT(m[0].v_camera, 1.6 * image);
}
