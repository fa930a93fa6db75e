// The reference path tracer against closed forms: an absorbing sphere in front of a uniform
// environment (L = Le exp(-tau)) and the volume white furnace (albedo 1, uniform environment:
// L = L_env everywhere). Means within 3 standard errors, fixed seeds.
#include <gtest/gtest.h>

#include "render/path/path_tracer.h"
#include "render/run/run_config.h"

using namespace vpm;

namespace {

std::unique_ptr<Scene> sphere_in_environment(double sigma_t, double albedo, double g, double env) {
    const std::string text = R"(
[render]
width = 4
height = 4
[camera]
position = [0, 0, 5]
look_at = [0, 0, 0]
[[lights]]
type = "environment"
radiance = )" + std::to_string(env) + R"(
[[media]]
type = "homogeneous"
shape = "sphere"
radius = 1.0
sigma_t_scale = )" + std::to_string(sigma_t) + R"(
albedo = )" + std::to_string(albedo) + R"(
g = )" + std::to_string(g) + "\n";
    return RunConfig::build(parse_config(text, "furnace.toml", ".")).scene;
}

struct Estimate {
    double mean = 0.0, se = 0.0;
};

// Mean of the green channel over n independent estimates along `ray`.
Estimate estimate(const Integrator& integrator, const Ray& ray, int n, uint64_t seed) {
    double sum = 0.0, sum2 = 0.0;
    for (int i = 0; i < n; ++i) {
        Rng rng(seed, uint64_t(i));
        const double l = integrator.radiance(ray, rng)[1];
        sum += l;
        sum2 += l * l;
    }
    Estimate e;
    e.mean = sum / n;
    e.se = std::sqrt(std::max(0.0, sum2 / n - e.mean * e.mean) / n);
    return e;
}

}  // namespace

TEST(PathTracer, AbsorbingSphereAttenuatesTheEnvironment) {
    const double sigma_t = 0.8, env = 2.0;
    auto scene = sphere_in_environment(sigma_t, 0.0, 0.0, env);
    PathTracer pt(*scene);
    // Through the centre (chord 2) and off-centre at height 0.6 (chord 2 sqrt(1 - 0.36) = 1.6).
    for (double h : {0.0, 0.6}) {
        const Ray ray{Vec3(0, h, 5), Vec3(0, 0, -1)};
        const double expected = env * std::exp(-sigma_t * 2.0 * std::sqrt(1.0 - h * h));
        const Estimate e = estimate(pt, ray, 40000, 1);
        EXPECT_NEAR(e.mean, expected, 3.0 * e.se) << "h = " << h;
        EXPECT_GT(e.se, 0.0);
    }
}

TEST(PathTracer, VolumeWhiteFurnace) {
    for (double g : {0.0, 0.7, -0.5}) {
        auto scene = sphere_in_environment(2.0, 1.0, g, 1.5);
        PathTracer pt(*scene);
        const Estimate e = estimate(pt, Ray{Vec3(0.2, 0.1, 5), Vec3(0, 0, -1)}, 20000, 7);
        EXPECT_NEAR(e.mean, 1.5, 3.0 * e.se) << "g = " << g;
        EXPECT_LT(e.se, 0.02);   // decisive: a 4% energy loss would be ~3 SE away
    }
}

TEST(PathTracer, FurnaceLosesEnergyWithAlbedoBelowOne) {
    // The same test must detect a missing albedo factor: at albedo 0.9 the sphere is darker.
    auto scene = sphere_in_environment(2.0, 0.9, 0.0, 1.5);
    PathTracer pt(*scene);
    const Estimate e = estimate(pt, Ray{Vec3(0.2, 0.1, 5), Vec3(0, 0, -1)}, 20000, 7);
    EXPECT_LT(e.mean + 5.0 * e.se, 1.5);
}

TEST(PathTracer, MaxDepthZeroSeesOnlyTheAttenuatedEnvironment) {
    auto scene = sphere_in_environment(1.0, 1.0, 0.0, 1.0);
    WalkSettings walk;
    walk.max_depth = 0;
    PathTracer pt(*scene, walk);
    const Estimate e = estimate(pt, Ray{Vec3(0, 0, 5), Vec3(0, 0, -1)}, 40000, 3);
    EXPECT_NEAR(e.mean, std::exp(-2.0), 3.0 * e.se);
}
