// `vpm make-sky`: writes a lat-long EXR of the requested size whose sun disc lies where the map
// convention (scene/lights/latlong_map.h) and --sun-elevation / --sun-azimuth put it, and which loads as
// an environment light that sees the sun there.
#include <gtest/gtest.h>

#include <cmath>

#include "render/image_io.h"
#include "scene/lights/latlong_map.h"
#include "scene/lights/light_registry.h"

#include "../support/vpm_process.h"

using namespace vpm;
using namespace vpm::test;

TEST(MakeSkyCli, WritesTheSunWhereTheOptionsPutIt) {
    ScratchDir dir;
    const Outcome o = run_vpm("make-sky --out " + quote(dir.path / "sub" / "sky.exr") +
                                  " --width 64 --height 32 --sun-elevation 20 --sun-azimuth 90 --sun-radius 6",
                              dir.path);
    ASSERT_EQ(o.code, 0) << o.err;
    EXPECT_NE(o.out.find("64 x 32"), std::string::npos) << o.out;
    const Image sky = read_exr(dir.path / "sub" / "sky.exr");
    ASSERT_EQ(sky.width, 64);
    ASSERT_EQ(sky.height, 32);
    // Brightest texel: azimuth 90 = +X, three quarters across; elevation 20 degrees above the
    // horizon row (theta = 70 degrees: row 70 / 180 * 32 = 12.4).
    int bx = 0, by = 0;
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 64; ++x)
            if (luminance(sky.at(x, y)) > luminance(sky.at(bx, by))) bx = x, by = y;
    EXPECT_NEAR(bx, 48, 1) << bx;
    EXPECT_EQ(by, 12);
    for (float v : sky.rgb) ASSERT_TRUE(std::isfinite(v) && v >= 0.0f);
    // Loaded as a light, the sun is seen along (cos 20, sin 20, 0) and not opposite it.
    auto doc = parse_config("[[lights]]\ntype = 'environment'\nfile = 'sub/sky.exr'\n", "sky.toml", dir.path);
    toml::table resolved;
    Params root(doc, &resolved);
    auto tables = root.tables("lights");
    auto light = make_light(tables.at(0));
    const double e = 20.0 * kPi / 180.0;
    const Vec3 sun(std::cos(e), std::sin(e), 0.0);
    EXPECT_GT(luminance(light->escaped_radiance(sun)), 50.0 * luminance(light->escaped_radiance(Vec3(-sun.x(), sun.y(), 0))));
    // And sampling the light finds it: most samples come from within the disc.
    Rng rng(4, 4);
    LightSample s;
    int in_disc = 0;
    for (int i = 0; i < 2000; ++i) in_disc += light->sample_incident(Vec3::Zero(), rng, s) && s.wi.dot(sun) > std::cos(0.15);
    EXPECT_GT(in_disc, 1000);
}
