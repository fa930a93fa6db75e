// Lights at infinity aiming half their photons at the region the camera sees (issue 24:
// scene/lights/emission_bounds.h, scene/camera_region.h). The mixture must leave every photon's
// expected power, and so the map, unchanged: checked per direction against the exact silhouette
// areas, within 4 standard errors.
#include <gtest/gtest.h>

#include "config/config_file.h"
#include "config/params.h"
#include "core/sampling/rng.h"
#include "scene/camera_region.h"
#include "scene/lights/emission_bounds.h"
#include "scene/scene.h"
#include "support/sample_statistics.h"
#include "support/scene_from_config.h"

using namespace vpm;

namespace {

const Bounds3 kBox{Vec3(-1000, -500, -2000), Vec3(1500, 700, 900)};
const Bounds3 kFocus{Vec3(-3, -1, 2), Vec3(1, 2, 4)};

std::unique_ptr<Scene> build_scene(const std::string& text) { return test::scene_from_config(text, 16, 16, "focus.toml"); }

}  // namespace

// For a fixed direction the lines' mean 1/density is the box's silhouette area (the photons' mean
// power is unchanged), the mean over the lines that meet the focus is the focus's silhouette area,
// and each nested level's share of the lines (plus the outer levels' fair shares) meets the focus.
// Every line starts outside the box and crosses it.
TEST(EmissionFocus, MixtureKeepsTheSilhouetteMeasures) {
    EmissionBounds eb;
    eb.set(kBox);
    eb.set_focus(kFocus);
    ASSERT_TRUE(eb.focused());
    const std::vector<Bounds3> levels = eb.focus_levels();
    // Growing kFocusGrowth-fold per level from about 5 to 2500 wide, the first the focus itself,
    // each inside the next and in the box.
    ASSERT_GE(levels.size(), 5u);
    EXPECT_EQ(levels[0].lo, kFocus.lo);
    EXPECT_EQ(levels[0].hi, kFocus.hi);
    for (size_t j = 1; j < levels.size(); ++j) {
        EXPECT_TRUE(levels[j].contains(levels[j - 1].lo) && levels[j].contains(levels[j - 1].hi)) << j;
        EXPECT_TRUE(kBox.contains(levels[j].lo) && kBox.contains(levels[j].hi)) << j;
    }
    EmissionBounds focus;
    focus.set(kFocus);
    Rng rng(7, 3);
    for (const Vec3& d : {Vec3(0, -1, 0), Vec3(1, 0, 0), Vec3(0.3, -0.8, 0.52).normalized(), Vec3(-1, 2, -3).normalized()}) {
        const double a_box = eb.projected_area(d), a_focus = focus.projected_area(d);
        test::Sample area, area_meeting, meets;
        for (int i = 0; i < 400000; ++i) {
            const EmissionLine line = eb.sample_line(d, rng.uniform(), rng.uniform(), rng.uniform());
            const Ray ray{line.origin, d};
            ASSERT_FALSE(kBox.contains(line.origin));
            double t0, t1;
            ASSERT_TRUE(kBox.intersect(ray, kInfinity, t0, t1));
            const bool hit = kFocus.intersect(ray, kInfinity, t0, t1);
            area.add(line.area);
            area_meeting.add(hit ? line.area : 0.0);
            meets.add(hit ? 1.0 : 0.0);
        }
        EXPECT_NEAR(area.mean(), a_box, 4.0 * area.se()) << d.transpose();
        EXPECT_NEAR(area_meeting.mean(), a_focus, 4.0 * area_meeting.se()) << d.transpose();
        double share = a_focus / a_box;
        for (const Bounds3& level : levels) {
            EmissionBounds l;
            l.set(level);
            share += a_focus / l.projected_area(d);
        }
        share /= double(levels.size() + 1);
        EXPECT_NEAR(meets.mean(), share, 4.0 * meets.se()) << d.transpose();
        EXPECT_GT(meets.mean(), 0.1);   // without the focus: a_focus / a_box, about 1e-5
    }
}

// A focus that is not much smaller than the box is ignored: the same lines as without it, from the
// same random numbers, so scenes the camera sees whole render as before.
TEST(EmissionFocus, LargeFocusChangesNothing) {
    EmissionBounds eb;
    eb.set(Bounds3{Vec3(-1, -1, -1), Vec3(1, 1, 1)});
    eb.set_focus(Bounds3{Vec3(-0.9, -0.9, -0.9), Vec3(0.8, 0.9, 0.9)});
    EXPECT_FALSE(eb.focused());
    eb.set_focus(Bounds3{Vec3(5, 5, 5), Vec3(6, 6, 6)});   // outside the box
    EXPECT_FALSE(eb.focused());
    eb.set_focus(Bounds3{});
    EXPECT_FALSE(eb.focused());
    Rng rng(1, 1);
    const Vec3 d = Vec3(0.2, -0.9, 0.1).normalized();
    for (int i = 0; i < 100; ++i) {
        const double u0 = rng.uniform(), u1 = rng.uniform(), u2 = rng.uniform();
        const EmissionLine line = eb.sample_line(d, u0, u1, u2);
        EXPECT_EQ(line.origin, eb.sample_origin(d, u0, u1, u2));
        EXPECT_EQ(line.area, eb.projected_area(d));
    }
}

// Scene::build finds what the camera sees and focuses the sky and the sun on it: a camera looking
// at a small part of a medium a thousand times wider. The photons' mean power is still power().
TEST(EmissionFocus, SceneFocusesLightsAtInfinityOnWhatTheCameraSees) {
    const std::string scene_text = R"(
[camera]
position = [0, 0, 3]
look_at = [0, 0, 0]
fov = 30
[[media]]
type = "homogeneous"
shape = "box"
min = [-1000, -1000, -1000]
max = [1000, 1000, 1000]
sigma_t_scale = 1
albedo = 0.9
[[lights]]
type = "environment"
radiance = 0.5
[[lights]]
type = "directional"
direction = [0, -1, 0]
irradiance = 2
[[lights]]
type = "point"
position = [0, 0, 0]
intensity = 1
)";
    auto scene = build_scene(scene_text);
    const Bounds3 region = camera_seen_region(*scene);
    ASSERT_FALSE(region.empty());
    EXPECT_LT((region.hi - region.lo).norm(), 100.0);   // about 2 mean free paths ahead of the camera
    EXPECT_TRUE(region.contains(Vec3(0, 0, 2)));
    int focused = 0;
    for (const std::string& line : scene->build_log) focused += line.find("aimed at the region the camera sees") != std::string::npos;
    EXPECT_EQ(focused, 2);
    for (int l = 0; l < 2; ++l) {
        const Light& light = *scene->lights[l];
        const double power = light.power()[0];
        Rng rng(5, l);
        test::Sample p;
        int near_camera = 0;
        for (int i = 0; i < 200000; ++i) {
            const EmissionSample e = light.sample_emission(rng);
            p.add(e.power[0]);
            double t0, t1;
            near_camera += region.intersect(e.ray, kInfinity, t0, t1);
        }
        EXPECT_NEAR(p.mean(), power, 4.0 * p.se()) << "light " << l;
        EXPECT_GT(near_camera, 0.1 * 200000) << "light " << l;   // without the focus: about 1e-5
    }
}
