// Where the auto pilot's pixels go (render/plan/pilot_pixels.h): over the pixels that can vary, each
// figure their average times their share of the image. A small object in an empty image must get
// all the pilot's pixels and the same image-average variance as the old block centres measure
// (within their standard error), and an image that sees something everywhere must keep the block
// centres exactly.
#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <vector>

#include "core/sampling/rng.h"
#include "photon/map/photon_map.h"
#include "render/plan/map_noise_pilot.h"
#include "render/plan/pilot_pixels.h"
#include "scene/camera.h"
#include "support/synthetic_pilot_hooks.h"

using namespace vpm;

TEST(PilotPixels, EverywhereSeenKeepsTheBlockCentres) {
    const PilotPixels p = choose_pilot_pixels(48, 32, 8, 16, [](int, int) { return true; });
    EXPECT_EQ(p.seen_fraction, 1.0);
    ASSERT_EQ(p.pixels.size(), 64u);
    ASSERT_EQ(p.spread.size(), 256u);
    EXPECT_TRUE(p.background.empty());
    for (int j = 0; j < 64; ++j) EXPECT_EQ(p.pixels[size_t(j)], block_centre(j, 8, 48, 32));
    for (int j = 0; j < 256; ++j) EXPECT_EQ(p.spread[size_t(j)], block_centre(j, 16, 48, 32));
}

TEST(PilotPixels, ASmallObjectGetsEveryPixel) {
    // A disc of radius 10 in a 128 x 128 image: 314 of 16384 pixels, 2% of the image.
    auto inside = [](int x, int y) { return (x - 90) * (x - 90) + (y - 40) * (y - 40) <= 100; };
    const PilotPixels p = choose_pilot_pixels(128, 128, 8, 16, inside);
    EXPECT_NEAR(p.seen_fraction, 314.0 / 16384.0, 0.01);
    std::set<std::pair<int, int>> distinct;
    for (const auto& [x, y] : p.pixels) {
        EXPECT_TRUE(inside(x, y));
        distinct.insert({x, y});
    }
    for (const auto& [x, y] : p.spread) EXPECT_TRUE(inside(x, y));
    for (const auto& [x, y] : p.background) EXPECT_FALSE(inside(x, y));
    EXPECT_EQ(p.background.size(), 64u);
    // The candidates in the disc (about 6 of the 32 x 32 grid), every one used.
    EXPECT_GE(distinct.size(), 4u);
}

TEST(PilotPixels, TheImageAverageVarianceIsKeptWhereMostPixelsAreEmpty) {
    // Synthetic hooks: a disc of uniform samples (variance 1/12) in an otherwise constant image. The
    // image's mean per-pixel variance is (1/12) x the disc's share; the pilot must read it with or
    // without the `sees` hook, and with it from every one of its 64 pixels in the disc.
    constexpr int kSide = 64;
    const Camera camera(Vec3(0, 0, 4), Vec3(0, 0, 0), Vec3(0, 1, 0), 40.0, kSide, kSide);
    const double half = std::tan(20.0 * kPi / 180.0);
    auto in_disc = [&](const Ray& r) {
        const double u = r.dir.x() / -r.dir.z() / half, v = r.dir.y() / -r.dir.z() / half;   // -1 .. 1
        return (u - 0.3) * (u - 0.3) + (v + 0.2) * (v + 0.2) <= 0.3 * 0.3;
    };
    MapNoisePilotHooks hooks = test::synthetic_pilot_hooks([&](const Ray& r, Rng& rng) { return Rgb::Constant(in_disc(r) ? 0.5 + rng.uniform() : 1.0); });
    const PhotonMap map;
    const double share = kPi * 0.3 * 0.3 / 4.0;   // of the [-1, 1]^2 image
    const double image = share / 12.0;
    const auto blocks = measure_gathers(camera, map, {{"collision", true}}, hooks, 5, 0);
    hooks.sees = in_disc;
    const auto seen = measure_gathers(camera, map, {{"collision", true}}, hooks, 5, 0);
    // With the hook all 64 + 256 pixels sample the disc: the estimate is within 5% (the 32 x 32
    // candidates' share is within a few % of the disc's area; the variance of 64 x 8 + 256 x 2
    // samples of a uniform has a 5% standard error).
    EXPECT_NEAR(seen[0].v_camera, image, 0.12 * image);
    // The block centres put about 5 of 64 pixels in it: a far noisier read of the same figure.
    EXPECT_NEAR(blocks[0].v_camera, image, 0.6 * image);
    EXPECT_NEAR(seen[0].mean, blocks[0].mean, 0.05);
}
