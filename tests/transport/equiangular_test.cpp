// Equiangular sampling of point and spot lights along a segment, MIS-combined with distance
// sampling (transport/equiangular.h): its density is normalised; the path tracer's single
// scattering with it matches a quadrature of the closed form in a homogeneous sphere (and so does the
// distance sampling alone, with a larger spread); in a grid medium (the blob), with multiple
// scattering and a spot light, it agrees with distance sampling alone within the standard errors;
// and the beam gather's single scattering (segment_direct_light) matches the same quadrature.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "core/henyey_greenstein.h"
#include "render/path/path_tracer.h"
#include "scene/scene.h"
#include "support/sample_statistics.h"
#include "support/scene_from_config.h"
#include "transport/equiangular.h"
#include "transport/segment_direct_light.h"

using namespace vpm;

namespace {

std::unique_ptr<Scene> scene_from(const std::string& text) {
    return test::scene_from_config("[camera]\nposition = [0, 0, 4]\nlook_at = [0, 0, 0]\n" + text, 8, 8, "equiangular.toml");
}

const double kSigmaT = 2.0, kAlbedo = 0.8, kG = 0.3;
const Vec3 kLight(0.1, 0.2, 0.0);
const std::string kPoint = "[[lights]]\ntype = 'point'\nposition = [0.1, 0.2, 0.0]\nintensity = 1\n";
const std::string kSphere =
    "[[media]]\ntype = 'homogeneous'\nshape = 'sphere'\nradius = 1\nsigma_t_scale = 2\nalbedo = 0.8\ng = 0.3\n";
const std::string kBlob = "[[media]]\ntype = 'grid'\nfile = '" VPM_SOURCE_DIR
                          "/media/blob.vdb'\ntransform = { scale = 1.3333333333333333 }\nsigma_t_scale = 6\nalbedo = 0.9\ng = 0.5\n";

// A camera ray passing 0.1 from the light.
const Ray kRay{Vec3(0, 0, 4), (Vec3(0.1, 0.1, 0.0) - Vec3(0, 0, 4)).normalized()};

// Single scattering of the point light along kRay in the unit sphere (the light inside it, so its
// shadow ray lies in the medium): the integral over the chord [a, b] of
// exp(-sigma_t (t - a)) sigma_s hg(wi . dir) I / d^2 exp(-sigma_t d), by a midpoint rule in the
// equiangular angle, where the integrand is smooth (its error ~1e-8 of the value).
double single_scattering_closed_form() {
    const Vec3 o = kRay.origin, w = kRay.dir;
    const double bq = o.dot(w), disc = std::sqrt(bq * bq - o.squaredNorm() + 1.0);
    const double a = -bq - disc, b = -bq + disc;
    const Vec3 d = kLight - o;
    const double t0 = d.dot(w), h = (d - t0 * w).norm();
    const double ta = std::atan2(a - t0, h), tb = std::atan2(b - t0, h);
    const int m = 200000;
    double sum = 0.0;
    for (int i = 0; i < m; ++i) {
        const double theta = ta + (tb - ta) * (i + 0.5) / m;
        const double t = t0 + h * std::tan(theta);
        const Vec3 x = kRay.at(t);
        const Vec3 to = kLight - x;
        const double dist = to.norm();
        const double f = std::exp(-kSigmaT * (t - a)) * kSigmaT * kAlbedo * hg_eval((to / dist).dot(w), kG) / (dist * dist) *
                         std::exp(-kSigmaT * dist);
        const double dt = h / (std::cos(theta) * std::cos(theta)) * (tb - ta) / m;
        sum += f * dt;
    }
    return sum;
}

test::Sample path_traced(const Scene& scene, const Ray& ray, int max_depth, bool equiangular, int n, uint64_t stream) {
    WalkSettings walk;
    walk.max_depth = max_depth;
    walk.equiangular = equiangular;
    const PathTracer pt(scene, walk);
    Rng rng(11, stream);
    test::Sample s;
    for (int i = 0; i < n; ++i) s.add(pt.radiance(ray, rng)[1]);
    return s;
}

double z_of(const test::Sample& a, const test::Sample& b) {
    return (a.mean() - b.mean()) / std::sqrt(a.se() * a.se() + b.se() * b.se());
}

}  // namespace

TEST(Equiangular, DensityIsNormalisedOnTheSegment) {
    const auto scene = scene_from(kPoint + kSphere);
    const EquiangularSegment segment(*scene, kRay, kInfinity);
    ASSERT_FALSE(segment.empty());
    // The ray's interval in the medium's bounds (the sphere's box): the density integrates to 1 over
    // it and is 0 outside.
    double a = 0.0, b = 0.0;
    ASSERT_TRUE(scene->media[0]->bounds().intersect(kRay, kInfinity, a, b));
    const int m = 400000;
    double total = 0.0;
    for (int i = 0; i < m; ++i) total += segment.pdf(0, a + (b - a) * (i + 0.5) / m) * (b - a) / m;
    EXPECT_NEAR(total, 1.0, 1e-3);
    EXPECT_EQ(segment.pdf(0, a - 1e-3), 0.0);
    EXPECT_EQ(segment.pdf(0, b + 1e-3), 0.0);
    // A light that is not a point light gets no density and no weight.
    const auto sky = scene_from("[[lights]]\ntype = 'environment'\nradiance = 1\n" + kSphere);
    EXPECT_TRUE(EquiangularSegment(*sky, kRay, kInfinity).empty());
    // Outside the medium's bounds there is nothing to sample.
    EXPECT_TRUE(EquiangularSegment(*scene, Ray{Vec3(0, 0, 4), Vec3(0, 0, 1)}, kInfinity).empty());
}

TEST(Equiangular, PathTracerSingleScatteringMatchesTheClosedForm) {
    const auto scene = scene_from(kPoint + kSphere);
    const double expected = single_scattering_closed_form();
    const test::Sample on = path_traced(*scene, kRay, 1, true, 100000, 1);
    const test::Sample off = path_traced(*scene, kRay, 1, false, 100000, 2);
    std::printf("closed form %.6f; equiangular + distance %.6f +- %.6f (sd %.4f); distance only %.6f +- %.6f (sd %.4f)\n",
                expected, on.mean(), on.se(), std::sqrt(on.var()), off.mean(), off.se(), std::sqrt(off.var()));
    EXPECT_NEAR(on.mean(), expected, 4.0 * on.se());
    EXPECT_NEAR(off.mean(), expected, 4.0 * off.se());
    // 0.1 from the light, distance sampling's NEE has the heavy tail the equiangular sample removes.
    EXPECT_LT(on.var(), 0.25 * off.var());
}

TEST(Equiangular, BeamSingleScatteringMatchesTheClosedForm) {
    const auto scene = scene_from(kPoint + kSphere);
    const double expected = single_scattering_closed_form();
    Rng a(5, 1), b(5, 2);
    uint64_t rays = 0;
    test::Sample on, off;
    for (int i = 0; i < 50000; ++i) {
        on.add(segment_direct_light(*scene, kRay, kInfinity, 4, a, rays, true)[1]);
        off.add(segment_direct_light(*scene, kRay, kInfinity, 4, b, rays, false)[1]);
    }
    std::printf("closed form %.6f; beam equiangular %.6f +- %.6f; march points only %.6f +- %.6f\n", expected, on.mean(),
                on.se(), off.mean(), off.se());
    EXPECT_NEAR(on.mean(), expected, 4.0 * on.se());
    EXPECT_NEAR(off.mean(), expected, 4.0 * off.se());
    EXPECT_LT(on.var(), 0.5 * off.var());
}

TEST(Equiangular, GridMediumWithMultipleScatteringAgreesWithDistanceSampling) {
    const auto scene = scene_from(kPoint + kBlob);
    // Single scattering: the equiangular sample lowers the spread; up to three scattering events:
    // both agree (the later vertices' NEE near the light is heavy-tailed either way, so their
    // standard errors are not compared).
    for (const int depth : {1, 3}) {
        const test::Sample on = path_traced(*scene, kRay, depth, true, 30000, 3);
        const test::Sample off = path_traced(*scene, kRay, depth, false, 30000, 4);
        std::printf("blob, max_depth %d: equiangular %.6f +- %.6f, distance only %.6f +- %.6f, z %.2f\n", depth, on.mean(),
                    on.se(), off.mean(), off.se(), z_of(on, off));
        EXPECT_GT(on.mean(), 0.0);
        EXPECT_LT(std::abs(z_of(on, off)), 4.0) << depth;
        if (depth == 1) {
            EXPECT_LT(on.se(), off.se());
        }
    }
}

TEST(Equiangular, SpotLightAgreesWithDistanceSampling) {
    // The cone (40 degrees about -y) cuts the camera ray: samples outside it count 0.
    const std::string spot =
        "[[lights]]\ntype = 'spot'\nposition = [0.1, 0.2, 0.0]\nlook_at = [0.1, -1, 0.3]\nintensity = 2\ncone_angle = 40\n";
    const auto scene = scene_from(spot + kSphere);
    const test::Sample on = path_traced(*scene, kRay, 2, true, 60000, 5);
    const test::Sample off = path_traced(*scene, kRay, 2, false, 60000, 6);
    std::printf("spot, max_depth 2: equiangular %.6f +- %.6f, distance only %.6f +- %.6f, z %.2f\n", on.mean(), on.se(),
                off.mean(), off.se(), z_of(on, off));
    EXPECT_GT(on.mean(), 0.0);
    EXPECT_LT(std::abs(z_of(on, off)), 4.0);
}
