// `vpm make-sky`: writes a lat-long EXR of the requested size whose sun disc lies where the map
// convention (scene/lights/latlong_map.h) and --sun-elevation / --sun-azimuth put it, and which loads as
// an environment light that sees the sun there.
#include <gtest/gtest.h>

#include <cmath>

#include "render/run/image_io.h"
#include "scene/lights/latlong_map.h"
#include "scene/lights/light_registry.h"

#include "support/vpm_process.h"

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

// Issue 24: NaN, Inf and radiances whose texels a float EXR cannot hold are refused before any
// work (exit 2, one short line naming the option, no file), and NaN angles no longer drop the sun.
TEST(MakeSkyCli, RefusesNonFiniteAndUnrepresentableValues) {
    ScratchDir dir;
    const fs::path out = dir.path / "sky.exr";
    for (const std::string bad : {"--sun-radiance nan", "--sun-radiance inf", "--sun-radiance 1e300",
                                  "--sun-radiance 1e999", "--sun-radiance -1", "--sky-radiance nan",
                                  "--sky-radiance 1e31", "--sun-elevation nan", "--sun-azimuth nan",
                                  "--sun-azimuth -inf", "--sun-radius nan", "--sun-elevation 91"}) {
        const Outcome o = run_vpm("make-sky --width 8 --height 4 --out " + quote(out) + " " + bad, dir.path);
        EXPECT_EQ(o.code, 2) << bad << ": " << o.err;
        EXPECT_TRUE(o.one_line()) << o.err;
        EXPECT_NE(o.err.find(bad.substr(0, bad.find(' '))), std::string::npos) << o.err;
        EXPECT_LT(o.err.size(), 200u) << o.err;   // no 309-digit DBL_MAX
        EXPECT_FALSE(fs::exists(out)) << bad;
    }
    // The largest allowed radiance still gives finite texels.
    const Outcome o = run_vpm("make-sky -q --width 8 --height 4 --sun-radius 30 --sun-radiance 1e30 --sky-radiance 1e30 --out " + quote(out), dir.path);
    ASSERT_EQ(o.code, 0) << o.err;
    for (float v : read_exr(out).rgb) ASSERT_TRUE(std::isfinite(v));
}

// Issue 24: a large map reports its progress (one line per interval when stderr is a file), and
// two runs give the same map (rows in parallel, power sums in row order).
TEST(MakeSkyCli, ReportsProgressAndIsDeterministic) {
    ScratchDir dir;
    const Outcome o = run_vpm("make-sky --width 64 --height 32 --out " + quote(dir.path / "a.exr"), dir.path,
                              "VPM_PROGRESS_SECONDS=0 ");
    ASSERT_EQ(o.code, 0) << o.err;
    EXPECT_NE(o.err.find("make-sky: 100%"), std::string::npos) << o.err;
    const Outcome q = run_vpm("make-sky -q --width 64 --height 32 --out " + quote(dir.path / "b.exr"), dir.path,
                              "VPM_PROGRESS_SECONDS=0 ");
    ASSERT_EQ(q.code, 0) << q.err;
    EXPECT_EQ(q.err, "");
    EXPECT_EQ(q.out.substr(q.out.find(':')), o.out.substr(o.out.find(':')));   // same size, mean and sun share
    EXPECT_EQ(read_exr(dir.path / "a.exr").rgb, read_exr(dir.path / "b.exr").rgb);
}
