// photon/map/photon_cell_counts.h: the cell counts certify "at least k photons within r" only where a
// brute-force count agrees, and certify most balls that hold many more than k photons, also far
// from the origin (coordinates near 1e6) and with every photon at one point.
#include <gtest/gtest.h>

#include <cstdio>
#include <vector>

#include "core/sampling/rng.h"
#include "photon/map/photon_cell_counts.h"
#include "photon/map/photon_map.h"

namespace vpm {
namespace {

size_t within(const PhotonMap& map, const Vec3& x, double r) {
    size_t n = 0;
    for (size_t i = 0; i < map.size(); ++i) n += (map.position(i) - x).squaredNorm() <= r * r;
    return n;
}

PhotonMap clustered_map(const Vec3& offset, Rng& rng) {
    // A uniform cube of side 2 and tight clusters of 50 photons, like the walks of a dense medium.
    std::vector<PhotonInput> in;
    for (int i = 0; i < 4000; ++i) {
        PhotonInput p;
        p.position = offset + Vec3(2 * rng.uniform() - 1, 2 * rng.uniform() - 1, 2 * rng.uniform() - 1);
        p.power = Rgb::Ones();
        in.push_back(p);
    }
    for (int c = 0; c < 20; ++c) {
        const Vec3 centre = offset + Vec3(2 * rng.uniform() - 1, 2 * rng.uniform() - 1, 2 * rng.uniform() - 1);
        for (int i = 0; i < 50; ++i) {
            PhotonInput p;
            p.position = centre + 0.01 * Vec3(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5);
            p.power = Rgb::Ones();
            in.push_back(p);
        }
    }
    return PhotonMap(in);
}

TEST(PhotonCellCounts, CertifiesOnlyWhatACountConfirms) {
    for (const Vec3& offset : {Vec3(0, 0, 0), Vec3(1e6, -2e6, 3e5)}) {
        Rng rng(5, 1);
        const PhotonMap map = clustered_map(offset, rng);
        const PhotonCellCounts cells(map);
        int certified = 0, plenty = 0, certified_plenty = 0;
        for (int q = 0; q < 3000; ++q) {
            const Vec3 x = offset + Vec3(2.4 * rng.uniform() - 1.2, 2.4 * rng.uniform() - 1.2, 2.4 * rng.uniform() - 1.2);
            const double r = 0.02 + 1.5 * rng.uniform();
            const size_t k = 1 + size_t(16 * rng.uniform());
            const size_t n = within(map, x, r);
            const bool sure = cells.surely_holds(x, r, k);
            if (sure) {
                ++certified;
                ASSERT_GE(n, k) << "x " << x.transpose() << " r " << r << " k " << k;
            }
            // A ball that holds 200 times k photons: its cell (1/22 to 1/174 of the ball's volume) holds k
            // for most (74% here; the others' centres lie outside the photons' box or their cell is small).
            if (n >= 200 * k) {
                ++plenty;
                certified_plenty += sure;
            }
        }
        std::printf("offset %g: %d of 3000 balls certified, %d of %d holding 200 k\n", offset[0], certified, certified_plenty, plenty);
        EXPECT_GT(certified, 300);
        EXPECT_GT(plenty, 100);
        EXPECT_GT(certified_plenty, plenty / 2) << certified_plenty << " of " << plenty;
    }
}

TEST(PhotonCellCounts, CoincidentPhotonsAndEmptyMaps) {
    std::vector<PhotonInput> in(40);
    for (auto& p : in) {
        p.position = Vec3(3, 3, 3);
        p.power = Rgb::Ones();
    }
    const PhotonCellCounts cells{PhotonMap(in)};
    EXPECT_TRUE(cells.surely_holds(Vec3(3, 3, 3), 0.1, 40));
    EXPECT_FALSE(cells.surely_holds(Vec3(3, 3, 3), 0.1, 41));
    EXPECT_FALSE(cells.surely_holds(Vec3(3.2, 3, 3), 0.1, 1));   // outside the (point) box
    EXPECT_FALSE(cells.surely_holds(Vec3(3, 3, 3), 0.0, 1));
    EXPECT_FALSE(PhotonCellCounts(PhotonMap()).surely_holds(Vec3::Zero(), 1.0, 1));
    EXPECT_FALSE(PhotonCellCounts().surely_holds(Vec3::Zero(), 1.0, 1));
}

}  // namespace
}  // namespace vpm
