// analysis/metrics/seen_lights.h: the pixels where the scene shows an area light, straight or
// through glass, for the metrics' "exclude directly seen lights" mask.
#include <gtest/gtest.h>

#include <cmath>
#include <numeric>

#include "analysis/metrics/seen_lights.h"
#include "core/error.h"
#include "render/run/run_config.h"

using namespace vpm;

namespace {

RunConfig glass(std::vector<std::string> sets) {
    sets.push_back("render.width=64");
    sets.push_back("render.height=64");
    return RunConfig::load(VPM_SOURCE_DIR "/configs/glass_sphere_fog.toml", sets);
}

size_t marked(const std::vector<uint8_t>& v) { return size_t(std::accumulate(v.begin(), v.end(), 0)); }

}  // namespace

TEST(SeenLights, ALightInViewMarksItsDiscAndNothingElse) {
    // The sphere light (radius 0.1) moved in front of the glass, 3.30 from the camera, on the view
    // axis' side: a disc of 0.0303 rad, 2.67 pixels in radius at 64x64 and a 40-degree fov.
    // The glass ball, which would also show it, is moved out of view.
    const RunConfig c = glass({"lights.0.center=[0.0, 0.5, 1.0]", "lights.0.radius=0.1", "shapes.0.center=[0.0, 50.0, 0.0]"});
    const std::vector<uint8_t> seen = seen_light_pixels(*c.scene, 64, 64);
    const double focal = 32.0 / std::tan(20.0 * kPi / 180.0);
    const Vec3 to_light = Vec3(0.0, 0.5, 1.0) - Vec3(0.0, 1.3, 4.2);
    const double r = std::asin(0.1 / to_light.norm()) * focal;
    // Every pixel the disc covers, and those its edge crosses (any of 16 sub-pixel rays), no more.
    EXPECT_GE(double(marked(seen)), kPi * (r - 1.0) * (r - 1.0));
    EXPECT_LE(double(marked(seen)), kPi * (r + std::sqrt(2.0)) * (r + std::sqrt(2.0)));
    // Where the camera sees the light's centre (projected through camera.h's pinhole).
    int cx = -1, cy = -1;
    double best = kInfinity;
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) {
            const Ray ray = c.scene->camera.generate_ray(x + 0.5, y + 0.5);
            const double off = (ray.dir.normalized() - to_light.normalized()).norm();
            if (off < best) {
                best = off;
                cx = x;
                cy = y;
            }
        }
    EXPECT_EQ(seen[size_t(cy) * 64 + size_t(cx)], 1);
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x)
            if (std::hypot(x - cx, y - cy) > r + 3.0) {
                EXPECT_EQ(seen[size_t(y) * 64 + size_t(x)], 0) << x << "," << y;
            }
}

TEST(SeenLights, TheGlintThroughTheGlassIsSeenAndGoesWithTheGlass) {
    // configs/glass_sphere_fog.toml: the light is above the frame; the glass sphere shows it.
    const RunConfig c = glass({});
    const size_t through_glass = marked(seen_light_pixels(*c.scene, 64, 64));
    EXPECT_GT(through_glass, 0u);
    EXPECT_LT(through_glass, 64u * 64u / 20u);
    // With the glass moved out of view nothing shows the light.
    const RunConfig away = glass({"shapes.0.center=[0.0, 50.0, 0.0]"});
    EXPECT_EQ(marked(seen_light_pixels(*away.scene, 64, 64)), 0u);
}

TEST(SeenLights, MasksImagesOfTheCamerasAspectAndSaysSo) {
    const RunConfig c = glass({});
    // Half the resolution: the same rays, scaled; the light in view (radius 2.67 pixels at 64x64)
    // covers about a quarter of the pixels.
    const RunConfig in_view = glass({"lights.0.center=[0.0, 0.5, 1.0]", "lights.0.radius=0.1", "shapes.0.center=[0.0, 50.0, 0.0]"});
    const size_t sixty_four = marked(seen_light_pixels(*in_view.scene, 64, 64)), half = marked(seen_light_pixels(*in_view.scene, 32, 32));
    EXPECT_GE(half, 4u);
    EXPECT_LE(half, sixty_four / 2);
    const size_t full = marked(seen_light_pixels(*c.scene, 64, 64));
    EXPECT_THROW(seen_light_pixels(*c.scene, 64, 32), Error);
    PixelMask mask(64, 64);
    exclude_seen_lights(mask, *c.scene, "glass_sphere_fog.toml");
    EXPECT_EQ(mask.compared_count(), 64u * 64u - full);
    EXPECT_NE(mask.describe().find("exclude lights seen in glass_sphere_fog.toml"), std::string::npos) << mask.describe();
}
