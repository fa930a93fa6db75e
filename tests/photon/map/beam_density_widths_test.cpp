// Density widths (photon/map/beam_density_widths.h) on a Poisson field of beams.
// - The 1D estimate with the widths fixed before the query, sum over the beams crossed within their
//   own width of K_1(u / r_j) / sin theta (constant kernel: 1 / (2 r_j sin theta)), is unbiased for the
//   field's line density times the query's length: over independent fields, within 3 standard errors.
// - Every piece gets one positive width; a field of half the density gets wider widths.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "core/sampling/rng.h"
#include "core/sampling/sampling.h"
#include "photon/map/beam_density_widths.h"
#include "photon/map/photon_beam_bvh.h"

using namespace vpm;

namespace {

// n beams of length 1, centres uniform in the cube [-1.5, 1.5]^3, isotropic directions: near the
// centre a stationary field of beam length n / 27 per unit volume.
std::vector<PhotonBeam> poisson_field(size_t n, Rng& rng) {
    std::vector<PhotonBeam> beams(n);
    for (PhotonBeam& b : beams) {
        const Vec3 centre(3.0 * rng.uniform() - 1.5, 3.0 * rng.uniform() - 1.5, 3.0 * rng.uniform() - 1.5);
        const double u1 = rng.uniform(), u2 = rng.uniform();
        b.dir = sample_uniform_sphere(u1, u2);
        b.length = 1.0;
        b.origin = centre - 0.5 * b.dir;
        b.power = Rgb::Ones();
    }
    return beams;
}

double median(std::vector<double> v) {
    std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(v.size() / 2), v.end());
    return v[v.size() / 2];
}

}  // namespace

TEST(BeamDensityWidths, FixedWidthEstimateIsUnbiasedOnAPoissonField) {
    const size_t n = 2000, k = 8;
    const int fields = 600;
    const double truth = double(n) / 27.0;   // line density x the unit query's length
    const auto unbounded = [](const Vec3&) { return kInfinity; };
    double sum = 0.0, sum2 = 0.0, crossed = 0.0;
    for (int f = 0; f < fields; ++f) {
        Rng rng(20261206, uint64_t(f));
        const std::vector<PhotonBeam> beams = poisson_field(n, rng);
        const double piece = PhotonBeamBvh::automatic_piece_length(beams);
        const BeamDensityWidths w = beam_density_widths(beams, piece, k, unbounded);
        const PhotonBeamBvh bvh(beams, w.widths, piece, true);
        // A unit query at the centre, its direction drawn apart from the field.
        const Vec3 d = sample_uniform_sphere(rng.uniform(), rng.uniform());
        const Vec3 o = -0.5 * d;
        double estimate = 0.0;
        bvh.for_each_crossed(o, d, 1.0, [&](const BeamCrossing& c, double r) {
            estimate += 1.0 / (2.0 * r * c.sin_theta);
            crossed += 1.0;
        });
        sum += estimate;
        sum2 += estimate * estimate;
    }
    const double mean = sum / fields, se = std::sqrt((sum2 / fields - mean * mean) / (fields - 1));
    std::printf("Poisson field, density widths k = %zu: %.4f +- %.4f of the truth, %.1f beams crossed per query\n", k,
                mean / truth, se / truth, crossed / fields);
    EXPECT_NEAR(mean, truth, 3.0 * se);
    EXPECT_LT(se, 0.05 * truth);   // resolved: the check could fail
}

TEST(BeamDensityWidths, EveryPieceGetsAWidthThatGrowsAsTheDensityFalls) {
    Rng rng(7, 0);
    const std::vector<PhotonBeam> dense = poisson_field(2000, rng), sparse = poisson_field(1000, rng);
    const auto unbounded = [](const Vec3&) { return kInfinity; };
    const double piece = PhotonBeamBvh::automatic_piece_length(dense);
    const BeamDensityWidths a = beam_density_widths(dense, piece, 8, unbounded);
    const BeamDensityWidths b = beam_density_widths(sparse, piece, 8, unbounded);
    size_t pieces = 0;
    for (const PhotonBeam& beam : dense) pieces += PhotonBeamBvh::pieces(beam, piece);
    ASSERT_EQ(a.widths.size(), pieces);
    for (double r : a.widths) EXPECT_TRUE(std::isfinite(r) && r > 0.0);
    EXPECT_EQ(a.bounded, 0u);
    // r ~ 1 / lambda: half the density, about twice the width (the middle beams, away from the faces).
    const double ratio = median(b.widths) / median(a.widths);
    EXPECT_GT(ratio, 1.6);
    EXPECT_LT(ratio, 2.5);
    // A bound caps every width and is counted.
    const BeamDensityWidths c = beam_density_widths(dense, piece, 8, [](const Vec3&) { return 1e-4; });
    for (double r : c.widths) EXPECT_EQ(r, 1e-4);
    EXPECT_EQ(c.bounded, c.queries);
}
