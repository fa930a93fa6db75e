// The walk steps every random walk shares (transport/walk_steps.h, transport/mis.h): the power
// heuristic's weights sum to one, Russian roulette keeps the throughput's expectation, the diffuse
// bounce is cosine-distributed on the side of the normal, and spawned rays leave the surface.
#include <gtest/gtest.h>

#include <cmath>

#include "transport/mis.h"
#include "transport/walk_steps.h"

using namespace vpm;

TEST(Mis, PowerHeuristicWeightsSumToOne) {
    for (double f : {1e-6, 0.1, 1.0, 3.0, 1e6})
        for (double g : {0.0, 1e-6, 0.5, 2.0, 1e6}) {
            EXPECT_NEAR(power_heuristic(f, g) + (g > 0.0 ? power_heuristic(g, f) : 0.0), 1.0, 1e-12) << f << " " << g;
            EXPECT_GE(power_heuristic(f, g), 0.0);
        }
    EXPECT_EQ(power_heuristic(kInfinity, 1.0), 1.0);
    EXPECT_EQ(light_sample_weight(false, 0.3, 0.7), 1.0);   // MIS off: light sampling weighs 1
    EXPECT_EQ(light_sample_weight(true, 0.0, 0.7), 1.0);    // delta light: nothing else finds it
    EXPECT_NEAR(light_sample_weight(true, 0.3, 0.7), 0.09 / (0.09 + 0.49), 1e-15);
}

// E[throughput after roulette] equals the throughput before it (0 when the path ends), for a
// throughput below and above the survival cap; before rr_depth every path survives untouched.
TEST(WalkSteps, RussianRouletteKeepsTheExpectation) {
    for (double t : {0.05, 0.4, 3.0}) {
        Rng rng(11, 5);
        const int n = 400000;
        double s = 0.0, s2 = 0.0;
        for (int i = 0; i < n; ++i) {
            Rgb throughput = Rgb(t, 0.5 * t, 0.25 * t);
            const double v = survive_roulette(throughput, 6, 5, rng) ? throughput[0] : 0.0;
            s += v;
            s2 += v * v;
        }
        const double mean = s / n, se = std::sqrt((s2 / n - mean * mean) / n);
        EXPECT_NEAR(mean, t, 4.0 * se + 1e-12) << t;
    }
    Rng rng(1, 1);
    Rgb low = Rgb::Constant(1e-9);
    EXPECT_TRUE(survive_roulette(low, 4, 5, rng));
    EXPECT_EQ(low[0], 1e-9);
}

// Inside glass a camera path's throughput carries the refraction's 1 / eta^2 (1 / 2.25 at ior 1.5),
// which leaving the glass undoes: with radiance_scale = 1 / 2.25 the roulette judges the throughput
// as 1 (survives with kRouletteMaxSurvival, a survivor weighs 1 / 2.25 / 0.999, not 1), and it
// still keeps the expectation.
TEST(WalkSteps, RouletteJudgesThroughputOverTheRadianceScale) {
    const double scale = 1.0 / 2.25;
    Rng rng(3, 8);
    const int n = 400000;
    double s = 0.0, s2 = 0.0;
    int survived = 0;
    for (int i = 0; i < n; ++i) {
        Rgb throughput = Rgb::Constant(scale);
        const bool alive = survive_roulette(throughput, 6, 5, rng, scale);
        if (alive) {
            ++survived;
            EXPECT_DOUBLE_EQ(throughput[0], scale / kRouletteMaxSurvival);
        }
        const double v = alive ? throughput[0] : 0.0;
        s += v;
        s2 += v * v;
    }
    const double mean = s / n, se = std::sqrt((s2 / n - mean * mean) / n);
    EXPECT_NEAR(mean, scale, 4.0 * se + 1e-12);
    // Survival frequency 0.999 (binomial standard error ~5e-5), where the unscaled roulette gives 0.444.
    EXPECT_NEAR(double(survived) / n, kRouletteMaxSurvival, 4.0 * std::sqrt(0.999 * 0.001 / n));
}

// A walk at albedo 0.99 with roulette at every collision: the throughput of a surviving walk stays
// at most 1 / kRouletteMaxSurvival (the cap once was 0.95, and it grew as (0.99 / 0.95)^n: 1.04^n, an
// estimator of unbounded variance), and its expectation after 300 collisions is 0.99^300 (4 SE).
TEST(WalkSteps, RouletteKeepsDeepWalksBoundedInAHighAlbedoMedium) {
    Rng rng(7, 3);
    const int walks = 200000, steps = 300;
    const double albedo = 0.99;
    double s = 0.0, s2 = 0.0, largest = 0.0;
    for (int i = 0; i < walks; ++i) {
        Rgb throughput = Rgb::Ones();
        bool alive = true;
        for (int n = 1; n <= steps && alive; ++n) {
            throughput *= albedo;
            alive = survive_roulette(throughput, n, 1, rng);
            if (alive) largest = std::max(largest, throughput.maxCoeff());
        }
        const double v = alive ? throughput[0] : 0.0;
        s += v;
        s2 += v * v;
    }
    const double mean = s / walks, se = std::sqrt((s2 / walks - mean * mean) / walks);
    EXPECT_LE(largest, 1.0 / kRouletteMaxSurvival + 1e-12);
    EXPECT_NEAR(mean, std::pow(albedo, steps), 4.0 * se);
}

// Cosine-weighted: E[cos] = 2/3 and E[cos^2] = 1/2 about the normal, never below the surface;
// the ray starts off the surface on the side it leaves towards.
TEST(WalkSteps, DiffuseBounceIsCosineDistributedAboveTheSurface) {
    SurfaceHit hit;
    hit.position = Vec3(1e3, -2.0, 0.5);
    hit.normal = Vec3(1, 2, -2).normalized();
    Rng rng(9, 9);
    const int n = 200000;
    double c1 = 0.0, c2 = 0.0;
    for (int i = 0; i < n; ++i) {
        const Ray ray = diffuse_bounce(hit, rng);
        const double c = ray.dir.dot(hit.normal);
        ASSERT_GT(c, 0.0);
        ASSERT_NEAR(ray.dir.norm(), 1.0, 1e-12);
        ASSERT_GT((ray.origin - hit.position).dot(hit.normal), 0.0);
        c1 += c;
        c2 += c * c;
    }
    // Standard errors: var(cos) = 1/2 - 4/9 = 1/18, var(cos^2) = 1/3 - 1/4 = 1/12.
    EXPECT_NEAR(c1 / n, 2.0 / 3.0, 4.0 * std::sqrt(1.0 / 18.0 / n));
    EXPECT_NEAR(c2 / n, 0.5, 4.0 * std::sqrt(1.0 / 12.0 / n));
    // A ray spawned into the surface leaves from below it.
    const Ray into = spawn_ray(hit, -hit.normal);
    EXPECT_LT((into.origin - hit.position).dot(hit.normal), 0.0);
}
