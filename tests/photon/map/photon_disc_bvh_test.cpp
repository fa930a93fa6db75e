// The photon-disc BVH returns exactly the photons a brute-force loop over the foot-point rule finds
// (random rays, rays grazing a ball, axis-parallel rays, rays starting inside balls, zero-length
// and negative segments, coordinates of 1e6), and leaves out balls without a finite radius.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include "core/sampling/rng.h"
#include "core/sampling/sampling.h"
#include "photon/map/photon_disc_bvh.h"

using namespace vpm;

namespace {

std::set<uint32_t> brute_force(const std::vector<Vec3>& c, const std::vector<double>& r, const Vec3& o, const Vec3& d,
                               double tmax) {
    std::set<uint32_t> s;
    if (!(tmax >= 0.0)) return s;
    for (size_t i = 0; i < c.size(); ++i) {
        if (!std::isfinite(r[i]) || !(r[i] > 0.0)) continue;
        const Vec3 v = c[i] - o;
        const double t = v.dot(d);
        if (t < 0.0 || t > tmax) continue;
        if (std::max(0.0, v.squaredNorm() - t * t) < r[i] * r[i]) s.insert(uint32_t(i));
    }
    return s;
}

std::set<uint32_t> bvh_query(const PhotonDiscBvh& bvh, const Vec3& o, const Vec3& d, double tmax) {
    std::set<uint32_t> s;
    bvh.for_each_crossed(o, d, tmax, [&](uint32_t i, double, double) { EXPECT_TRUE(s.insert(i).second) << "twice: " << i; });
    return s;
}

}  // namespace

TEST(PhotonDiscBvh, QueriesEqualABruteForceLoop) {
    for (double scale : {1.0, 1e6}) {
        Rng rng(21, uint64_t(scale));
        const Vec3 offset = scale > 1.0 ? Vec3(3e6, -1e6, 2e6) : Vec3::Zero();
        std::vector<Vec3> centres;
        std::vector<double> radii;
        for (int i = 0; i < 3000; ++i) {
            centres.push_back(offset + scale * (2.0 * Vec3(rng.uniform(), rng.uniform(), rng.uniform()) - Vec3::Ones()));
            radii.push_back(scale * 0.06 * (0.2 + rng.uniform()));
        }
        // coincident balls, a zero radius and a starved photon (infinite radius) are legal inputs
        centres.push_back(centres[5]);
        radii.push_back(radii[5]);
        radii[7] = 0.0;
        radii[9] = kInfinity;
        const PhotonDiscBvh bvh(centres, radii);
        EXPECT_EQ(bvh.size(), centres.size() - 2);
        size_t found = 0;
        for (int q = 0; q < 600; ++q) {
            Vec3 o = offset + scale * (2.0 * Vec3(rng.uniform(), rng.uniform(), rng.uniform()) - Vec3::Ones());
            Vec3 d = sample_uniform_sphere(rng.uniform(), rng.uniform());
            double tmax = scale * 3.0 * rng.uniform();
            switch (q % 6) {
                case 1: d = Vec3::UnitX(); break;                 // axis-parallel
                case 2: tmax = 0.0; break;                        // zero-length segment
                case 3: {                                         // grazing ball q: tangent to it
                    const size_t b = 100 + size_t(q) % 2000;
                    const Vec3 side = d.cross(Vec3(0.3, 1, 0.2)).normalized();
                    o = centres[b] + radii[b] * (1.0 - 1e-12) * side - 0.5 * tmax * d;
                    break;
                }
                case 4: o = centres[100 + size_t(q) % 2000]; break;    // starting at a ball's centre
                case 5: tmax = scale * 1e3; break;                 // longer than the scene
                default: break;
            }
            const std::set<uint32_t> expected = brute_force(centres, radii, o, d, tmax);
            EXPECT_EQ(bvh_query(bvh, o, d, tmax), expected) << "query " << q << " scale " << scale;
            found += expected.size();
        }
        EXPECT_GT(found, 1000u);   // the rays did cross discs
        EXPECT_TRUE(bvh_query(bvh, Vec3::Zero(), Vec3::UnitZ(), -1.0).empty());
    }
}

TEST(PhotonDiscBvh, EmptyAndStarvedMapsAnswerNothing) {
    const PhotonDiscBvh empty({}, {});
    EXPECT_TRUE(bvh_query(empty, Vec3::Zero(), Vec3::UnitX(), 10.0).empty());
    const PhotonDiscBvh starved({Vec3::Zero(), Vec3::UnitX()}, {kInfinity, kInfinity});
    EXPECT_EQ(starved.size(), 0u);
    EXPECT_TRUE(bvh_query(starved, Vec3(-1, 0, 0), Vec3::UnitX(), 10.0).empty());
}
