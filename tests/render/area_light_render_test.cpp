// Area lights seen by the integrators, and multiple importance sampling (transport/mis.h):
// a light seen directly has exactly its radiance; MIS on and off estimate the same image (within
// standard errors over independent runs) on the smoky Cornell box and on a medium under a small,
// bright quad; the photon map agrees with the path tracer on the Cornell box with its light in view.
#include <gtest/gtest.h>

#include <cstdio>

#include "render/path_tracer.h"
#include "render/photon_map_integrator.h"
#include "render/run_config.h"
#include "../support/render_statistics.h"

using namespace vpm;

namespace {

RunConfig lights_in_view(const std::vector<std::string>& overrides = {}) {
    // Camera on +z looking down -z at a one-sided quad facing it (u x v = +z), a second one-sided quad
    // facing away and a sphere light; nothing else.
    const std::string text = R"(
[render]
width = 8
height = 8
[camera]
position = [0, 0, 5]
look_at = [0, 0, 0]
[[lights]]
type = "quad"
center = [-1, 0, 0]
u = [0.3, 0, 0]
v = [0, 0.3, 0]
radiance = [5, 4, 3]
[[lights]]
type = "quad"
center = [1, 0, 0]
u = [0, 0.3, 0]
v = [0.3, 0, 0]
radiance = [5, 4, 3]
[[lights]]
type = "sphere"
center = [0, 1.2, 0]
radius = 0.4
radiance = [0.5, 6, 7]
)";
    return RunConfig::build(parse_config(text, "lights_in_view.toml", ".", overrides));
}

// Mean image value over `repeats` independent runs of `path` with each override set.
test::Sample brightness(const std::string& path, const std::vector<std::string>& overrides, int repeats) {
    return test::repeated_run_brightness(RunConfig::load(path, overrides), repeats);
}

void expect_same_mean(const test::Sample& a, const test::Sample& b, double sigmas, double relative_slack, const char* what) {
    const double se = std::sqrt(a.se() * a.se() + b.se() * b.se());
    std::printf("%s: %.6g +- %.3g vs %.6g +- %.3g\n", what, a.mean(), a.se(), b.mean(), b.se());
    EXPECT_NEAR(a.mean(), b.mean(), sigmas * se + relative_slack * b.mean()) << what << ": " << a.mean() << " +- " << a.se()
                                                                             << " vs " << b.mean() << " +- " << b.se();
    EXPECT_GT(a.se(), 0.0) << what;
    EXPECT_GT(b.se(), 0.0) << what;
}

}  // namespace

TEST(AreaLightRender, LightsSeenDirectlyHaveExactlyTheirRadiance) {
    for (const char* mis : {"render.mis=true", "render.mis=false"}) {
        const RunConfig config = lights_in_view({mis});
        const Scene& scene = *config.scene;
        const PathTracer pt(scene, WalkSettings{-1, 5, std::string(mis).find("true") != std::string::npos});
        const PhotonMapIntegrator pm(scene, photon_map_settings(config));   // no photon pass: nothing to gather
        for (const Integrator* integrator : {static_cast<const Integrator*>(&pt), static_cast<const Integrator*>(&pm)}) {
            Rng rng(1, 1);
            const Rgb front = integrator->radiance(Ray{Vec3(-1.1, 0.1, 5), Vec3(0, 0, -1)}, rng);
            EXPECT_EQ(front[0], 5.0);
            EXPECT_EQ(front[1], 4.0);
            EXPECT_EQ(front[2], 3.0);
            // The back of a one-sided quad is black (and opaque).
            EXPECT_EQ(integrator->radiance(Ray{Vec3(1.1, 0.1, 5), Vec3(0, 0, -1)}, rng).maxCoeff(), 0.0);
            const Rgb sphere = integrator->radiance(Ray{Vec3(0.1, 1.3, 5), Vec3(0, 0, -1)}, rng);
            EXPECT_EQ(sphere[1], 6.0);
            EXPECT_EQ(sphere[2], 7.0);
            EXPECT_EQ(integrator->radiance(Ray{Vec3(0.1, -1, 5), Vec3(0, 0, -1)}, rng).maxCoeff(), 0.0);
        }
    }
    // Two-sided: the back shows the same radiance.
    const RunConfig two = lights_in_view({"lights.1.two_sided=true"});
    Rng rng(1, 1);
    EXPECT_EQ(PathTracer(*two.scene).radiance(Ray{Vec3(1.1, 0.1, 5), Vec3(0, 0, -1)}, rng)[0], 5.0);
}

TEST(AreaLightRender, MisOnAndOffAgreeOnTheSmokyCornellBox) {
    const std::vector<std::string> small = {"render.width=16", "render.height=16", "render.spp=32"};
    std::vector<std::string> on = small, off = small;
    on.insert(on.end(), {"render.mis=true", "render.seed=3"});   // independent seeds: independent runs
    off.insert(off.end(), {"render.mis=false", "render.seed=4"});
    const std::string path = VPM_SOURCE_DIR "/configs/cornell_smoke_path.toml";
    expect_same_mean(brightness(path, on, 10), brightness(path, off, 10), 4.0, 0.0, "Cornell box, MIS on vs off");
}

TEST(AreaLightRender, MisOnAndOffAgreeInAMediumUnderASmallBrightQuad) {
    const std::vector<std::string> small = {"render.width=16", "render.height=16", "render.spp=64"};
    std::vector<std::string> on = small, off = small;
    on.insert(on.end(), {"render.mis=true", "render.seed=5"});
    off.insert(off.end(), {"render.mis=false", "render.seed=6"});
    const std::string path = VPM_SOURCE_DIR "/configs/small_light_smoke.toml";
    expect_same_mean(brightness(path, on, 10), brightness(path, off, 10), 4.0, 0.0, "small bright quad, MIS on vs off");
}

TEST(AreaLightRender, PhotonMapMatchesPathTracerOnTheCornellBoxWithItsLightInView) {
    const std::vector<std::string> small = {"render.width=16", "render.height=16", "render.spp=16", "photons.count=50000"};
    std::vector<std::string> pm = small, pt = small;
    pm.push_back("render.seed=7");
    pt.insert(pt.end(), {"render.integrator=path", "render.seed=8"});
    const std::string path = VPM_SOURCE_DIR "/configs/cornell_smoke.toml";
    // The corrected estimator is unbiased in the kNN count; what is left is the kernel's blur.
    expect_same_mean(brightness(path, pm, 6), brightness(path, pt, 6), 3.0, 0.02, "Cornell box, photon map vs path tracer");
}
