// Compression round trips of the stored photon record, with the bounds stated in photon.h.
#include <gtest/gtest.h>

#include <cmath>

#include "core/sampling/rng.h"
#include "core/sampling/sampling.h"
#include "photon/map/photon.h"
#include "photon/map/photon_map.h"

using namespace vpm;

TEST(PhotonCodec, BytesPerPhoton) {
    EXPECT_EQ(sizeof(Photon), 24u);
    EXPECT_EQ(bytes_per_photon(), 28u);
    EXPECT_LE(bytes_per_photon(), 32u);
}

TEST(PhotonCodec, MeasuredMemoryWithTreeAtMost32BytesPerPhoton) {
    Rng rng(7, 0);
    std::vector<PhotonInput> in(100000);
    for (auto& p : in) {
        p.position = Vec3(rng.uniform(), rng.uniform(), rng.uniform());
        p.power = Rgb::Constant(1.0);
    }
    const PhotonMap map(in);
    const double per = double(map.memory_bytes()) / double(map.size());
    EXPECT_LE(per, 32.0) << "measured " << per << " bytes per photon";
    EXPECT_GE(per, double(bytes_per_photon()));
}

TEST(PhotonCodec, DirectionRoundTripWithinBound) {
    Rng rng(11, 0);
    double worst = 0.0;
    auto check = [&](const Vec3& d) {
        uint16_t q[2];
        encode_direction(d, q);
        const Vec3 r = decode_direction(q);
        EXPECT_NEAR(r.norm(), 1.0, 1e-12);
        const double ang = std::atan2(d.cross(r).norm(), d.dot(r));
        worst = std::max(worst, ang);
    };
    for (int i = 0; i < 200000; ++i) {
        const double u1 = rng.uniform(), u2 = rng.uniform();
        check(sample_uniform_sphere(u1, u2));
    }
    for (int a = 0; a < 3; ++a) {
        check(Vec3::Unit(a));
        check(-Vec3::Unit(a));
    }
    check(Vec3(1e-9, -1e-9, -1).normalized());   // near the folded pole
    check(Vec3(1, 1, -1e-12).normalized());      // on the fold
    EXPECT_LE(worst, 7e-5) << "max angular error " << worst;
    EXPECT_GT(worst, 1e-6);   // quantisation is real: a test that cannot fail would be useless
}

TEST(PhotonCodec, PowerRoundTripWithinBound) {
    Rng rng(13, 0);
    const double scale = 3.7e-7;   // watts per photon of a typical map: far below binary16 range
    for (int i = 0; i < 100000; ++i) {
        const Rgb p(scale * rng.uniform(), scale * std::pow(10.0, -6.0 * rng.uniform()), scale);
        uint16_t q[3];
        encode_power(p, 1.0 / scale, q);
        const Rgb r = decode_power(q, scale);
        for (int c = 0; c < 3; ++c) {
            if (p[c] >= 0x1p-14 * scale) {
                ASSERT_LE(std::abs(r[c] - p[c]), 0x1p-11 * p[c]) << p[c];
            } else {
                ASSERT_LE(std::abs(r[c] - p[c]), 0x1p-25 * scale) << p[c];
            }
        }
    }
}

TEST(PhotonCodec, PositionRoundTripFarFromOrigin) {
    Rng rng(17, 0);
    const Vec3 offset(1.0e4, -3.0e5, 2.5e3);   // scene far from the origin
    std::vector<PhotonInput> in(5000);
    for (auto& p : in) {
        p.position = offset + Vec3(rng.uniform(), rng.uniform(), rng.uniform()) * 2.0;
        p.direction = sample_uniform_sphere(rng.uniform(), rng.uniform());
        p.power = Rgb(rng.uniform(), rng.uniform(), rng.uniform());
    }
    const PhotonMap map(in);
    const Vec3 c = map.centre();
    // every stored photon decodes to within the bound of some input photon; check via kNN k=1
    NeighbourList nl;
    double worst = 0.0;
    for (const auto& p : in) {
        ASSERT_EQ(map.knn(p.position, 1, kInfinity, nl), 1u);
        const Vec3 r = map.position(nl[0].index);
        for (int a = 0; a < 3; ++a) {
            const double bound = 0x1p-24 * std::abs(p.position[a] - c[a]) + 1e-15 * std::abs(p.position[a]);
            ASSERT_LE(std::abs(r[a] - p.position[a]), bound);
        }
        worst = std::max(worst, (r - p.position).norm());
        // decoded power and direction of that photon
        EXPECT_TRUE(((map.power(nl[0].index) - p.power).abs() <= 0x1p-11 * p.power + 0x1p-25).all());
        EXPECT_LE(std::acos(std::min(1.0, map.direction(nl[0].index).dot(p.direction))), 7e-5);
    }
    EXPECT_LT(worst, 1e-6);   // the same positions in absolute float coordinates would err ~2e-3
}
