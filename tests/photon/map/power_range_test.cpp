// Photons of very different power in one map (issue 12): each photon's power is stored relative to
// its own binary exponent, so a map holding a sky light's photons and a point light's photons 1e7
// times dimmer keeps both to binary16 precision. With the earlier map-wide scale the dim photons
// became subnormals of the brightest (step 2^-24 of it) or zero: the photon map of
// configs/inside_large_sphere.toml came out 2x too bright.
#include <gtest/gtest.h>

#include "core/sampling/rng.h"
#include "core/sampling/sampling.h"
#include "photon/map/photon_map.h"

using namespace vpm;

TEST(PhotonPowerRange, PhotonsOfAnyPowerShareOneMap) {
    Rng rng(21, 0);
    std::vector<PhotonInput> in(4000);
    for (size_t i = 0; i < in.size(); ++i) {
        in[i].position = sample_uniform_ball(rng.uniform(), rng.uniform(), rng.uniform());
        const double magnitude = std::pow(10.0, -12.0 + 24.0 * rng.uniform());   // 1e-12 .. 1e12 W
        in[i].power = magnitude * Rgb(rng.uniform() + 0.5, rng.uniform() + 0.5, 1.0);
    }
    in[0].power = Rgb::Zero();
    const PhotonMap map(in);
    NeighbourList nl;
    Rgb total = Rgb::Zero(), decoded = Rgb::Zero();
    for (const auto& p : in) {
        ASSERT_EQ(map.knn(p.position, 1, kInfinity, nl), 1u);
        const Rgb r = map.power(nl[0].index);
        for (int c = 0; c < 3; ++c) ASSERT_LE(std::abs(r[c] - p.power[c]), 0x1p-11 * p.power[c]) << p.power[c];
        total += p.power;
        decoded += r;
    }
    EXPECT_TRUE(((map.total_power() - total).abs() <= 1e-3 * total).all());
}
