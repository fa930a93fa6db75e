// Photon emission guided by what each direction reaches (scene/emission_guides.h,
// scene/lights/direction_guide.h). A guided light must emit the same expected power into every
// set of rays as before (checked against the unguided light on test functions of the photon's
// start and direction, within 4 standard errors of the difference), a light whose photons mostly
// reach nothing must be guided and one whose photons already land must not, and the choice and
// its figures must not change when the scene is scaled.
#include <gtest/gtest.h>

#include <functional>

#include "core/sampling/rng.h"
#include "scene/emission_guides.h"
#include "scene/lights/direction_guide.h"
#include "scene/scene.h"
#include "support/sample_statistics.h"
#include "support/scene_from_config.h"

using namespace vpm;

namespace {

// A dense sphere of radius r at the origin inside a faint haze 20 r wide; the light 3 r away.
std::string hazy_room(const std::string& light, double scale) {
    auto v = [&](double a, double b, double c) {
        return "[" + std::to_string(a * scale) + ", " + std::to_string(b * scale) + ", " + std::to_string(c * scale) + "]";
    };
    const std::string light_table =
        light == "point"  ? "type = \"point\"\nposition = " + v(3, 1, 0) + "\nintensity = 30.0\n"
        : light == "spot" ? "type = \"spot\"\nposition = " + v(3, 1, 0) + "\nlook_at = [0, 0, 0]\ncone_angle = 40.0\nintensity = 30.0\n"
                          : "type = \"sphere\"\ncenter = " + v(3, 1, 0) + "\nradius = " + std::to_string(0.25 * scale) + "\nradiance = 12.0\n";
    return "[camera]\nposition = " + v(0, 1, 6) + "\nlook_at = [0, 0, 0]\nfov = 30\n[[lights]]\n" + light_table +
           "[[media]]\ntype = \"homogeneous\"\nshape = \"sphere\"\ncenter = [0, 0, 0]\nradius = " + std::to_string(scale) +
           "\nsigma_t_scale = " + std::to_string(10.0 / scale) + "\nalbedo = 0.99\n" +
           "[[media]]\ntype = \"homogeneous\"\nshape = \"box\"\nmin = " + v(-10, -10, -10) + "\nmax = " + v(10, 10, 10) +
           "\nsigma_t_scale = " + std::to_string(0.002 / scale) + "\nalbedo = 0.9\n";
}

std::unique_ptr<Scene> build(const std::string& text) { return test::scene_from_config(text, 8, 8, "guide.toml"); }

// E[power x f(photon)] with and without the guide agree within 4 standard errors of their difference,
// for each test function.
void expect_same_emission(Light& light, const std::shared_ptr<const DirectionGuide>& guide,
                          const std::vector<std::function<double(const Ray&)>>& fs) {
    constexpr int kPhotons = 400000;
    std::vector<test::Sample> plain(fs.size()), guided(fs.size());
    Rng rng(11, 4);
    light.set_emission_guide(nullptr, 0.0);
    for (int i = 0; i < kPhotons; ++i) {
        const EmissionSample e = light.sample_emission(rng);
        for (size_t f = 0; f < fs.size(); ++f) plain[f].add(luminance(e.power) * fs[f](e.ray));
    }
    light.set_emission_guide(guide, kGuideShare);
    for (int i = 0; i < kPhotons; ++i) {
        const EmissionSample e = light.sample_emission(rng);
        for (size_t f = 0; f < fs.size(); ++f) guided[f].add(luminance(e.power) * fs[f](e.ray));
    }
    for (size_t f = 0; f < fs.size(); ++f) {
        const double se = std::hypot(plain[f].se(), guided[f].se());
        EXPECT_NEAR(guided[f].mean(), plain[f].mean(), 4.0 * se) << "test function " << f;
        EXPECT_GT(plain[f].mean(), 10.0 * se) << "test function " << f << " sees too little power to test";
    }
}

// Test functions of a photon: all of it, the rays towards the dense sphere, a cone away from it,
// and (for lights with extent) where on the light the photon starts.
std::vector<std::function<double(const Ray&)>> test_functions(const Vec3& light_centre) {
    const Vec3 to_sphere = (Vec3(0, 0, 0) - light_centre).normalized();
    return {
        [](const Ray&) { return 1.0; },
        [=](const Ray& r) { return r.dir.dot(to_sphere) > 0.94 ? 1.0 : 0.0; },
        [=](const Ray& r) { return r.dir.dot(to_sphere) < 0.9 ? 1.0 : 0.0; },
        [=](const Ray& r) { return r.dir.dot(to_sphere) > 0.9 && (r.origin - light_centre).y() >= 0.0 ? 1.0 : 0.0; },
    };
}

}  // namespace

TEST(DirectionGuide, DensityIntegratesToOneAndMatchesItsSamples) {
    std::vector<double> w(size_t(DirectionGuide::kColumns) * DirectionGuide::kRows, 0.0);
    Rng fill(3, 1);
    for (size_t i = 0; i < w.size(); ++i) w[i] = i % 7 == 0 ? 0.0 : fill.uniform();   // zeros between
    const DirectionGuide guide(w);
    double total = 0.0;
    for (int r = 0; r < DirectionGuide::kRows; ++r)
        for (int c = 0; c < DirectionGuide::kColumns; ++c) {
            const Vec3 d = DirectionGuide::direction(c, r, 0.5, 0.5);
            int cc = -1, rr = -1;
            DirectionGuide::cell_of(d, cc, rr);
            ASSERT_EQ(cc, c);
            ASSERT_EQ(rr, r);
            total += guide.pdf(d) * DirectionGuide::cell_solid_angle();
        }
    EXPECT_NEAR(total, 1.0, 1e-12);
    // Samples land only where the density is positive, and E[1 / pdf] over them is 4 pi minus the
    // solid angle of the zero cells (the importance-sampled measure of the support).
    Rng rng(5, 2);
    test::Sample inverse;
    for (int i = 0; i < 200000; ++i) {
        const Vec3 d = guide.sample(rng.uniform(), rng.uniform());
        ASSERT_NEAR(d.norm(), 1.0, 1e-12);
        const double p = guide.pdf(d);
        ASSERT_GT(p, 0.0);
        inverse.add(1.0 / p);
    }
    size_t zeros = 0;
    for (double x : w) zeros += x == 0.0;
    const double support = 4.0 * kPi * (1.0 - double(zeros) / double(w.size()));
    EXPECT_NEAR(inverse.mean(), support, 4.0 * inverse.se());
}

TEST(EmissionGuide, ALightBesideASmallDenseSphereInHazeIsGuidedAndEmitsTheSamePower) {
    for (const std::string type : {"point", "sphere", "spot"}) {
        SCOPED_TRACE(type);
        auto scene = build(hazy_room(type, 1.0));
        std::vector<double> weights;
        const EmissionGuideEstimate e = estimate_emission_guide(*scene, 0, weights);
        // The sphere covers 0.36 sr of 4 pi from the light (2.9%), of the spot's 40-degree cone 1.47 sr
        // (24%); the haze catches about 2% of the rest.
        EXPECT_TRUE(e.guided);
        EXPECT_NEAR(e.reach_own, type == "spot" ? 0.26 : 0.048, type == "spot" ? 0.03 : 0.01);
        EXPECT_GT(e.reach_mixture, (type == "spot" ? 2.0 : 4.0) * e.reach_own);
        expect_same_emission(*scene->lights[0], std::make_shared<const DirectionGuide>(weights), test_functions(Vec3(3, 1, 0)));
    }
}

TEST(EmissionGuide, TheMixtureIsUnbiasedEvenWhereTheGuideIsWrong) {
    // A guide pointing away from everything: the light's own half still covers every direction.
    std::vector<double> w(size_t(DirectionGuide::kColumns) * DirectionGuide::kRows, 0.0);
    w[5] = 1.0;
    auto guide = std::make_shared<const DirectionGuide>(w);
    for (const char* type : {"point", "sphere", "spot"}) {
        SCOPED_TRACE(type);
        auto scene = build(hazy_room(type, 1.0));
        expect_same_emission(*scene->lights[0], guide, test_functions(Vec3(3, 1, 0)));
    }
}

TEST(EmissionGuide, LightsWhosePhotonsLandAlreadyAreNotGuided) {
    // A point light outside a box emits over the box's silhouette: every photon enters it.
    auto lit_box = build(
        "[camera]\nposition = [0, 0, 5]\nlook_at = [0, 0, 0]\n[[lights]]\ntype = \"point\"\nposition = [3, 1, 0]\n"
        "intensity = 1.0\n[[media]]\ntype = \"homogeneous\"\nshape = \"box\"\nmin = [-1, -1, -1]\nmax = [1, 1, 1]\n"
        "sigma_t_scale = 1.0\n");
    std::vector<double> weights;
    const EmissionGuideEstimate box = estimate_emission_guide(*lit_box, 0, weights);
    EXPECT_FALSE(box.guided);
    EXPECT_GT(box.reach_own, 0.5);
    EXPECT_TRUE(lit_box->prepare_photon_emission().empty());
    // A light inside a dense medium: every direction collides.
    auto inside = build(
        "[camera]\nposition = [0, 0, 5]\nlook_at = [0, 0, 0]\n[[lights]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\n"
        "radius = 0.1\nradiance = 1.0\n[[media]]\ntype = \"homogeneous\"\nshape = \"sphere\"\ncenter = [0, 0, 0]\n"
        "radius = 2\nsigma_t_scale = 20.0\n");
    const EmissionGuideEstimate dense = estimate_emission_guide(*inside, 0, weights);
    EXPECT_FALSE(dense.guided);
    EXPECT_NEAR(dense.reach_own, 1.0, 1e-9);
}

TEST(EmissionGuide, TheSameChoiceAtEveryScale) {
    for (const char* type : {"point", "sphere", "spot"}) {
        SCOPED_TRACE(type);
        std::vector<double> w1, w2, w3;
        auto s1 = build(hazy_room(type, 1.0));
        auto s2 = build(hazy_room(type, 1e-3));
        auto s3 = build(hazy_room(type, 1e3));
        const EmissionGuideEstimate a = estimate_emission_guide(*s1, 0, w1);
        const EmissionGuideEstimate b = estimate_emission_guide(*s2, 0, w2);
        const EmissionGuideEstimate c = estimate_emission_guide(*s3, 0, w3);
        EXPECT_EQ(a.guided, b.guided);
        EXPECT_EQ(a.guided, c.guided);
        EXPECT_NEAR(b.reach_mixture, a.reach_mixture, 1e-6 * a.reach_mixture);
        EXPECT_NEAR(c.reach_mixture, a.reach_mixture, 1e-6 * a.reach_mixture);
        // The guide's weights are densities over directions: the same cell by cell.
        double diff = 0.0, sum = 0.0;
        for (size_t i = 0; i < w1.size(); ++i) {
            diff += std::abs(w1[i] - w2[i]) + std::abs(w1[i] - w3[i]);
            sum += w1[i];
        }
        EXPECT_LT(diff, 1e-6 * sum);
    }
}
