// Next-event estimation (transport/direct_light.h) and its MIS combination with phase sampling
// (transport/mis.h) against closed forms: a point light through a homogeneous sphere, and a sphere
// light seen from a point in a thin medium, where NEE alone, and NEE plus the phase-sampled walk
// that meets the light, must both give the light's irradiance times the isotropic phase function.
#include <gtest/gtest.h>

#include <cmath>

#include "config/params.h"
#include "core/math.h"
#include "core/sampling/sampling.h"
#include "scene/scene.h"
#include "transport/direct_light.h"
#include "transport/mis.h"
#include "transport/walk_steps.h"
#include "support/sample_statistics.h"
#include "support/scene_from_config.h"

using namespace vpm;

namespace {

std::unique_ptr<Scene> scene_from(const std::string& text) {
    return test::scene_from_config("[camera]\nposition = [0, 0, 5]\nlook_at = [0, 0, 0]\n" + text, 8, 8, "transport.toml");
}

// A homogeneous isotropic sphere of radius 1 at the origin with extinction sigma_t.
std::string sphere_medium(double sigma_t) {
    return "[[media]]\ntype = 'homogeneous'\nshape = 'sphere'\nradius = 1\nsigma_t_scale = " + std::to_string(sigma_t) +
           "\nalbedo = 0.5\ng = 0\n";
}

struct MeanAndError {
    double mean, se;
};

template <class F>
MeanAndError monte_carlo(int n, F sample) {
    test::Sample s;
    for (int i = 0; i < n; ++i) s.add(sample(i));
    return {s.mean(), s.se()};
}

}  // namespace

// A point light of intensity I at distance 3 from the sphere's centre: in-scattered radiance at the
// centre is (1 / 4 pi) I / 9 e^{-sigma_t} (one unit of path inside the sphere). Homogeneous media
// give transmittance in closed form, so every sample is exact.
TEST(DirectLight, PointLightThroughAHomogeneousSphereIsExact) {
    const auto scene = scene_from("[[lights]]\ntype = 'point'\nposition = [0, 3, 0]\nintensity = 7\n" + sphere_medium(1.5));
    Rng rng(1, 2);
    const Rgb l = direct_light_in_medium(*scene, Vec3::Zero(), Vec3(0, 0, -1), 0.0, rng);
    const double expected = 7.0 / 9.0 * std::exp(-1.5) / (4.0 * kPi);
    EXPECT_NEAR(l[1], expected, 1e-12 * expected);
}

// A sphere light (radius 0.25, radiance L) at distance 3 from a point in a nearly empty medium:
// in-scattered radiance = L (1 - cos theta_max) 2 pi / (4 pi), theta_max its angular radius.
// NEE alone (mis = false), and with MIS its NEE part plus the phase-sampled directions that meet
// the light weighted by EmissionWeighting::after, must both match within 4 standard errors.
TEST(DirectLight, SphereLightNeeAndMisCombinationMatchTheClosedForm) {
    const double L = 2.0, r = 0.25, d = 3.0;
    const auto scene = scene_from("[[lights]]\ntype = 'sphere'\ncenter = [0, 3, 0]\nradius = 0.25\nradiance = 2\n" +
                                  sphere_medium(1e-9));
    const double cos_max = std::sqrt(1.0 - (r / d) * (r / d));
    const double expected = L * (1.0 - cos_max) * 2.0 * kPi / (4.0 * kPi);
    const Vec3 x = Vec3::Zero(), view(0, 0, -1);
    const int n = 400000;
    Rng rng(3, 4);
    const MeanAndError nee = monte_carlo(n, [&](int) { return direct_light_in_medium(*scene, x, view, 0.0, rng)[1]; });
    // (the sphere light samples its cone of directions uniformly: every NEE sample is exact here)
    EXPECT_NEAR(nee.mean, expected, 4.0 * nee.se + 1e-9 * expected) << "NEE alone";

    const MeanAndError nee_mis =
        monte_carlo(n, [&](int) { return direct_light_in_medium(*scene, x, view, 0.0, rng, true)[1]; });
    const double phase_pdf = 1.0 / (4.0 * kPi);
    const MeanAndError walk = monte_carlo(n, [&](int) {
        const Vec3 dir = sample_uniform_sphere(rng.uniform(), rng.uniform());
        SurfaceHit hit;
        if (!scene->intersect(Ray{x, dir}, kInfinity, hit) || !hit.emitter) return 0.0;
        // phase / pdf = 1 for isotropic scattering sampled by its own pdf.
        return emitted_radiance(*scene, Ray{x, dir}, hit, EmissionWeighting::after(true, x, phase_pdf))[1];
    });
    EXPECT_NEAR(nee_mis.mean + walk.mean, expected, 4.0 * std::hypot(nee_mis.se, walk.se) + 1e-9 * expected)
        << "NEE + walk, MIS";
    // Each strategy alone carries only part of it: the weights really split the work.
    EXPECT_LT(nee_mis.mean, expected - 4.0 * nee_mis.se);
    EXPECT_GT(walk.mean, 4.0 * walk.se);
}
