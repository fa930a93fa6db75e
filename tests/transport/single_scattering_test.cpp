// The photon map's single scattering by both strategies (transport/single_scattering.h): unbiased
// against a quadrature of the closed-form transmittance under a constant sky and against NEE alone
// under a quad light, and a photon-map camera path that never uses its map (starved) is the path
// tracer's own path, MIS included: the same image, bit for bit.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "config/params.h"
#include "core/henyey_greenstein.h"
#include "core/math.h"
#include "render/run/run.h"
#include "render/run/run_config.h"
#include "transport/single_scattering.h"
#include "scene/scene.h"
#include "transport/direct_light.h"
#include "support/render_statistics.h"
#include "support/sample_statistics.h"
#include "support/scene_from_config.h"

using namespace vpm;

namespace {

std::unique_ptr<Scene> scene_from(const std::string& text) {
    return test::scene_from_config("[camera]\nposition = [0, 0, 5]\nlook_at = [0, 0, 0]\n" + text, 8, 8, "single.toml");
}

const char* kSphere = "[[media]]\ntype = 'homogeneous'\nshape = 'sphere'\nradius = 1\nsigma_t_scale = 1.5\nalbedo = 0.9\ng = 0\n";

// Light-only NEE and both strategies at x, n samples each (separate streams).
struct Pair {
    test::Sample nee, both;
};
Pair estimate(const Scene& scene, const Vec3& x, const Vec3& dir, double g, int n) {
    Pair p;
    Rng a(7, 1), b(7, 2);
    uint64_t rays = 0;
    for (int i = 0; i < n; ++i) {
        p.nee.add(direct_light_in_medium(scene, x, dir, g, a)[1]);
        p.both.add(single_scattering_both_strategies(scene, x, dir, g, b, rays)[1]);
    }
    return p;
}

}  // namespace

// Constant sky of radiance 1 around a homogeneous sphere (radius 1, sigma_t 1.5), point x off centre,
// forward scattering g = 0.6: L_ss = integral hg(w . dir) exp(-sigma_t d(x, w)) dw, d the distance
// to the sphere's surface, by a 1024 x 1024 midpoint rule (its error ~1e-6 of the value).
TEST(SingleScattering, BothStrategiesMatchTheQuadratureUnderAConstantSky) {
    const auto scene = scene_from("[[lights]]\ntype = 'environment'\nradiance = 1\n" + std::string(kSphere));
    const Vec3 x(0.55, 0.1, -0.2), dir = Vec3(0.3, -0.2, 1.0).normalized();
    const double g = 0.6, sigma_t = 1.5;
    double expected = 0.0;
    const int m = 1024;
    for (int i = 0; i < m; ++i)
        for (int j = 0; j < m; ++j) {
            const double mu = -1.0 + 2.0 * (i + 0.5) / m, phi = 2.0 * kPi * (j + 0.5) / m, s = std::sqrt(1.0 - mu * mu);
            const Vec3 w(s * std::cos(phi), s * std::sin(phi), mu);
            const double b = x.dot(w), d = -b + std::sqrt(b * b - x.squaredNorm() + 1.0);
            expected += hg_eval(w.dot(dir), g) * std::exp(-sigma_t * d) * (2.0 / m) * (2.0 * kPi / m);
        }
    const Pair p = estimate(*scene, x, dir, g, 200000);
    std::printf("sky: expected %.6f, NEE %.6f +- %.6f (sd %.4f), both %.6f +- %.6f (sd %.4f)\n", expected, p.nee.mean(),
                p.nee.se(), std::sqrt(p.nee.var()), p.both.mean(), p.both.se(), std::sqrt(p.both.var()));
    EXPECT_NEAR(p.nee.mean(), expected, 4.0 * p.nee.se());
    EXPECT_NEAR(p.both.mean(), expected, 4.0 * p.both.se());
    // Forward scattering: the bounce finds the bright directions the uniform light sample misses.
    EXPECT_LT(std::sqrt(p.both.var()), 0.8 * std::sqrt(p.nee.var()));
}

// A one-sided quad light just above the sphere: no closed form, but light-only NEE is unbiased, so
// both must agree within 4 combined standard errors; and at g = 0 the bounce must really carry part
// of it (both minus the weighted NEE alone, positive beyond 4 SE; at g = 0.8 towards -z it seldom
// meets the light).
TEST(SingleScattering, BothStrategiesAgreeWithNeeUnderAQuadLight) {
    const auto scene = scene_from(
        "[[lights]]\ntype = 'quad'\ncenter = [0, 1.3, 0]\nu = [0.6, 0, 0]\nv = [0, 0, 0.6]\nradiance = 5\n" +
        std::string(kSphere));
    const Vec3 x(0.2, 0.7, 0.1), dir(0, 0, -1);
    for (const double g : {0.0, 0.8}) {
        const Pair p = estimate(*scene, x, dir, g, 200000);
        const double z = (p.both.mean() - p.nee.mean()) / std::hypot(p.nee.se(), p.both.se());
        std::printf("quad, g %.1f: NEE %.6f +- %.6f, both %.6f +- %.6f, z %.2f\n", g, p.nee.mean(), p.nee.se(), p.both.mean(),
                    p.both.se(), z);
        EXPECT_LT(std::abs(z), 4.0) << "g " << g;
        if (g != 0.0) continue;
        Rng rng(9, 3);
        test::Sample nee_part;
        for (int i = 0; i < 200000; ++i) nee_part.add(direct_light_in_medium(*scene, x, dir, g, rng, true)[1]);
        EXPECT_GT(p.both.mean() - nee_part.mean(), 4.0 * std::hypot(p.both.se(), nee_part.se())) << "g " << g;
    }
}

TEST(SingleScattering, OnlyLightsABounceCanMeetTurnItOn) {
    EXPECT_TRUE(bounces_find_lights(*scene_from("[[lights]]\ntype = 'environment'\nradiance = 1\n" + std::string(kSphere))));
    EXPECT_TRUE(bounces_find_lights(*scene_from(
        "[[lights]]\ntype = 'sphere'\ncenter = [0, 3, 0]\nradius = 0.2\nradiance = 1\n" + std::string(kSphere))));
    EXPECT_FALSE(bounces_find_lights(*scene_from("[[lights]]\ntype = 'point'\nposition = [0, 3, 0]\nintensity = 1\n" +
                                                 std::string(kSphere))));
    EXPECT_FALSE(bounces_find_lights(
        *scene_from("[[lights]]\ntype = 'directional'\ndirection = [0, -1, 0]\nirradiance = 1\n" + std::string(kSphere))));
}

// A map of one photon is starved (k = 32): every collision continues, so the photon map's camera
// path is the path tracer's vertex for vertex, NEE and bounce weighted alike, and draws the same
// random numbers: the images must be identical, with render.mis on and off. Before, the continued
// paths weighed NEE 1 and counted no emission met: under a sky 4.3x the path tracer's variance.
TEST(SingleScattering, AStarvedPhotonMapRendersThePathTracersImage) {
    const std::string sky = "[[lights]]\ntype = 'environment'\nradiance = 1\n";
    const std::string quad = "[[lights]]\ntype = 'quad'\ncenter = [0, 1.6, 0]\nu = [0.5, 0, 0]\nv = [0, 0, 0.5]\nradiance = 5\n";
    for (const std::string& light : {sky, quad})
        for (const char* mis : {"true", "false"}) {
            const std::string text = "[render]\nwidth = 10\nheight = 10\nspp = 8\nmis = " + std::string(mis) +
                                     "\n[camera]\nposition = [0, 0, 4]\nlook_at = [0, 0, 0]\nfov = 40\n" + light + kSphere;
            auto load = [&](const std::string& integrator) {
                return RunConfig::build(parse_config(text, "starved.toml", ".",
                                                     {"render.integrator=\"" + integrator + "\"", "photons.count=1",
                                                      "photons.gather=\"collision\""}));
            };
            RunOptions o;
            o.progress = false;
            const RunResult pt = run(load("path"), o), pm = run(load("photon_map"), o);
            ASSERT_EQ(pt.image.rgb.size(), pm.image.rgb.size());
            EXPECT_EQ(0, std::memcmp(pt.image.rgb.data(), pm.image.rgb.data(), pt.image.rgb.size() * sizeof(float)))
                << (light == sky ? "sky" : "quad") << ", mis " << mis;
            EXPECT_GT(pm.image.mean(), 0.0);
        }
}
