// Homogeneous media: closed-form transmittance and the free-flight distribution.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "scene/media/homogeneous_medium.h"

using namespace vpm;

TEST(HomogeneousMedium, TransmittanceIsExpOfOpticalDepth) {
    const double sigma = 1.7;
    auto sphere = HomogeneousMedium::sphere(Vec3(1, 2, 3), 2.0, sigma, Rgb::Ones(), 0.0);
    auto box = HomogeneousMedium::box(Vec3(0, 0, 0), Vec3(1, 2, 3), sigma, Rgb::Ones(), 0.0);
    Rng rng;
    // Chord through a sphere at distance 1.2 from its centre: 2 sqrt(4 - 1.44).
    const Ray r1{Vec3(1, 3.2, -10), Vec3(0, 0, 1)};
    EXPECT_NEAR(sphere.transmittance(r1, kInfinity, rng), std::exp(-sigma * 2.0 * std::sqrt(4.0 - 1.44)), 1e-12);
    // Starting inside the box, stopping at tmax.
    const Ray r2{Vec3(0.5, 0.5, 0.5), Vec3(0, 0, 1)};
    EXPECT_NEAR(box.transmittance(r2, 1.0, rng), std::exp(-sigma * 1.0), 1e-12);
    EXPECT_NEAR(box.transmittance(r2, kInfinity, rng), std::exp(-sigma * 2.5), 1e-12);
    // Missing the medium entirely.
    EXPECT_EQ(box.transmittance(Ray{Vec3(5, 5, 5), Vec3(1, 0, 0)}, kInfinity, rng), 1.0);
}

TEST(HomogeneousMedium, FreeFlightFollowsTheExponentialCdf) {
    // Box of depth 3 along z, sigma 0.9: P(t < s) = 1 - exp(-0.9 s) for s < 3, escape mass exp(-2.7).
    const double sigma = 0.9, depth = 3.0;
    auto box = HomogeneousMedium::box(Vec3(-1, -1, 0), Vec3(1, 1, depth), sigma, Rgb::Ones(), 0.0);
    const Ray ray{Vec3(0, 0, -1), Vec3(0, 0, 1)};
    const int n = 200000;
    Rng rng(12, 0);
    std::vector<double> t;
    int escaped = 0;
    for (int i = 0; i < n; ++i) {
        const double s = box.sample_free_flight(ray, kInfinity, rng);
        if (s == kInfinity) ++escaped;
        else t.push_back(s - 1.0);
    }
    const double p_escape = std::exp(-sigma * depth);
    EXPECT_NEAR(double(escaped) / n, p_escape, 3.0 * std::sqrt(p_escape * (1 - p_escape) / n));
    std::sort(t.begin(), t.end());
    double d = 0.0;
    for (size_t i = 0; i < t.size(); ++i) {
        ASSERT_GE(t[i], 0.0);
        ASSERT_LT(t[i], depth);
        const double f = (1.0 - std::exp(-sigma * t[i])) / (1.0 - p_escape);   // conditional CDF
        d = std::max({d, std::abs(f - double(i) / t.size()), std::abs(f - double(i + 1) / t.size())});
    }
    EXPECT_LT(d, 1.95 / std::sqrt(double(t.size())));   // KS, alpha = 1e-3
}

TEST(HomogeneousMedium, ExtremeDensitiesStayFinite) {
    Rng rng(1, 1);
    for (double sigma : {1e-12, 1e-6, 1e6, 1e12}) {
        auto box = HomogeneousMedium::box(Vec3::Zero(), Vec3::Ones(), sigma, Rgb::Ones(), 0.0);
        const Ray ray{Vec3(0.5, 0.5, -1), Vec3(0, 0, 1)};
        const double tr = box.transmittance(ray, kInfinity, rng);
        EXPECT_TRUE(std::isfinite(tr) && tr >= 0.0 && tr <= 1.0);
        for (int i = 0; i < 1000; ++i) {
            const double s = box.sample_free_flight(ray, kInfinity, rng);
            ASSERT_TRUE(s == kInfinity || (s >= 1.0 && s <= 2.0)) << sigma << " " << s;
        }
    }
}
