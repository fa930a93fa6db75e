// The auto pilot's per-sample variance V_camera (render/plan/map_noise_pilot.h) where the camera noise
// lives in a thin band of the image that the 8 x 8 pilot pixels miss: the lit rim of a sphere held
// 75% of the march's noise in 1% of the pixels there, and the pilot read 1/7 of it (docs/studies/
// heldout_scenes.md, section 23), and the map's variance V_map where its noise lives in such a band. Synthetic hooks:
// every pixel returns 1 except one column.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <vector>

#include "core/sampling/rng.h"
#include "photon/map/photon_map.h"
#include "render/plan/map_noise_pilot.h"
#include "render/plan/relative_error.h"
#include "scene/camera.h"
#include "support/synthetic_pilot_hooks.h"

using namespace vpm;

namespace {

constexpr int kSide = 32;
// Column 27: no 8 x 8 pilot pixel (columns 2, 6, ..., 30) lies in it.
constexpr int kBand = 27;

Camera test_camera() { return Camera(Vec3(0, 0, 4), Vec3(0, 0, 0), Vec3(0, 1, 0), 40.0, kSide, kSide); }

// The pixel column a camera ray of test_camera() came from (its x in the image plane, either way round).
int column(const Camera& camera, const Ray& r) {
    const bool x_left = camera.generate_ray(0.5, 16.0).dir.x() < 0.0;
    const double t = r.dir.x() / -r.dir.z() / std::tan(20.0 * kPi / 180.0);   // -1 .. 1 across the image
    const int c = std::clamp(int((t + 1.0) * 0.5 * kSide), 0, kSide - 1);
    return x_left ? c : kSide - 1 - c;
}

}  // namespace

TEST(MapNoisePilot, CameraVarianceSeesABandTheCoarsePixelsMiss) {
    const Camera camera = test_camera();
    // Uniform samples of variance 1 / 12 in the band, 1 elsewhere: the image's mean per-pixel
    // variance is (1 / 12) / 32.
    MapNoisePilotHooks hooks = test::synthetic_pilot_hooks([&](const Ray& r, Rng& rng) { return Rgb::Constant(column(camera, r) == kBand ? 0.5 + rng.uniform() : 1.0); });
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

TEST(MapNoisePilot, MapVarianceSeesABandTheCoarsePixelsMiss) {
    // The same band, now as map noise: the two half maps differ by 1 there (every sample alike, so
    // none of it is the samples' own) and agree elsewhere. In a thin plume under a sun a tenth of the
    // 8 x 8 pixels held the map's noise and V_map read from them alone ranged over 0.18-2.8x its mean
    // over seeds (docs/studies/heldout_scenes.md section 30); the 16 x 16 grid's halves read it too.
    const Camera camera = test_camera();
    const PhotonMap map;
    const PhotonMap* in_force = nullptr;
    const PhotonMap* first_half = nullptr;
    std::atomic<int> traces{0};
    MapNoisePilotHooks hooks;
    hooks.use = [&](int, const PhotonMap* m) {
        in_force = m;
        if (m != &map && !first_half) first_half = m;
    };
    hooks.trace = [&](const Ray& r, Rng&) {
        ++traces;
        const double half = in_force == &map ? 0.0 : in_force == first_half ? 0.5 : -0.5;
        return Rgb::Constant(1.0 + (column(camera, r) == kBand ? half : 0.0));
    };
    hooks.counts = [&] {   // every sample one used query: the halves are built and traced
        CountedOperations c;
        c.queries = c.map_used = c.rays = double(traces.load());
        return c;
    };
    hooks.work = [](const CountedOperations& c) { return c.rays; };
    const auto m = measure_gathers(camera, map, {{"collision", true}}, hooks, 5, 0);
    ASSERT_EQ(m.size(), 1u);
    // 16 of the 16 x 16 centres lie in the band (t = 1 each), none of the 64 coarse ones: V_map(a) +
    // V_map(b) = 16 / 320 over the pixels, half of it per half map; the 8 x 8 pixels alone read 0.
    // Relative (render/plan/relative_error.h): every pixel's mean is 1, so each figure is over 1 + 0.01.
    const double w = relative_error_weight(1.0);
    EXPECT_NEAR(m[0].v_map_half, w * 0.5 * 16.0 / 320.0, 1e-12);
    // Its standard error: the spread of 16 ones among 304 zeros.
    const double p = 16.0 / 320.0;
    EXPECT_NEAR(m[0].v_map_half_se, w * 0.5 * std::sqrt(p * (1.0 - p) * 320.0 / 319.0 / 320.0), 1e-12);
    EXPECT_EQ(m[0].v_camera, 0.0);   // the full map's samples do not vary
}
