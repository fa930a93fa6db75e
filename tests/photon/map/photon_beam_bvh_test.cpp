// The photon-beam BVH (photon/map/photon_beam_bvh.h) returns exactly what a brute-force loop over
// photon_beam_crossing finds, for both queries: every beam within its own width (sample-point
// form) and the k nearest by line distance (balloon form), on random rays, rays grazing a plane of
// beams, axis-parallel rays, rays parallel to the beams, unbounded and zero-length segments; with
// whole beams and with beams cut into pieces (the same answers). The max-norm segment-box distance
// that orders the k-nearest traversal against the grown boxes' slab test.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <vector>

#include "core/sampling/rng.h"
#include "core/sampling/sampling.h"
#include "photon/map/photon_beam_bvh.h"
#include "photon/map/segment_box_distance.h"

using namespace vpm;

namespace {

std::map<uint32_t, BeamCrossing> brute_crossed(const std::vector<PhotonBeam>& beams, const std::vector<double>& widths,
                                               const Vec3& o, const Vec3& d, double tmax) {
    std::map<uint32_t, BeamCrossing> s;
    for (size_t i = 0; i < beams.size(); ++i) {
        BeamCrossing c;
        if (!photon_beam_crossing(o, d, tmax, beams[i].origin, beams[i].dir, beams[i].length, c)) continue;
        if (!(c.u < widths[i])) continue;
        c.index = uint32_t(i);
        s[uint32_t(i)] = c;
    }
    return s;
}

std::vector<BeamCrossing> brute_nearest(const std::vector<PhotonBeam>& beams, const Vec3& o, const Vec3& d, double tmax,
                                        size_t k, double bound) {
    std::vector<BeamCrossing> all;
    for (size_t i = 0; i < beams.size(); ++i) {
        BeamCrossing c;
        if (!photon_beam_crossing(o, d, tmax, beams[i].origin, beams[i].dir, beams[i].length, c) || !(c.u < bound)) continue;
        c.index = uint32_t(i);
        all.push_back(c);
    }
    std::sort(all.begin(), all.end(), [](const BeamCrossing& a, const BeamCrossing& b) {
        return a.u < b.u || (a.u == b.u && a.index < b.index);
    });
    if (all.size() > k) all.resize(k);
    return all;
}

struct Field {
    std::vector<PhotonBeam> beams;
    std::vector<double> widths;
};

// n beams in the unit cube: random directions and lengths, or (planar) all in the plane z = 0.5
// along x or y (zero-thickness boxes).
Field make_field(size_t n, bool planar, uint64_t seed) {
    Rng rng(seed, 0);
    Field f;
    for (size_t i = 0; i < n; ++i) {
        PhotonBeam b;
        b.origin = Vec3(rng.uniform(), rng.uniform(), planar ? 0.5 : rng.uniform());
        b.dir = planar ? (i % 2 ? Vec3::UnitX() : Vec3::UnitY()) : sample_uniform_sphere(rng.uniform(), rng.uniform());
        b.length = 0.5 * rng.uniform();
        b.power = Rgb::Ones();
        f.beams.push_back(b);
        f.widths.push_back(0.05 * rng.uniform());
    }
    return f;
}

void check_ray(const Field& f, const PhotonBeamBvh& swept, const PhotonBeamBvh& plain, const Vec3& o, const Vec3& d,
               double tmax, size_t& crossed, size_t& nonempty) {
    std::map<uint32_t, BeamCrossing> got;
    swept.for_each_crossed(o, d, tmax, [&](const BeamCrossing& c, double w) {
        EXPECT_EQ(w, f.widths[c.index]);
        EXPECT_TRUE(got.emplace(c.index, c).second) << "visited twice: " << c.index;
    });
    const auto want = brute_crossed(f.beams, f.widths, o, d, tmax);
    ASSERT_EQ(got.size(), want.size());
    for (const auto& [i, c] : want) {
        ASSERT_TRUE(got.count(i)) << i;
        EXPECT_EQ(got[i].t, c.t);
        EXPECT_EQ(got[i].u, c.u);
    }
    crossed += want.size();
    for (size_t k : {1, 4, 16}) {
        for (double bound : {kInfinity, 0.03}) {
            std::vector<BeamCrossing> near;
            plain.nearest(o, d, tmax, k, bound, near);
            const auto expect = brute_nearest(f.beams, o, d, tmax, k, bound);
            ASSERT_EQ(near.size(), expect.size()) << "k = " << k;
            for (size_t j = 0; j < near.size(); ++j) {
                EXPECT_EQ(near[j].index, expect[j].index) << "k = " << k << " rank " << j;
                EXPECT_EQ(near[j].u, expect[j].u);
            }
            if (!near.empty()) ++nonempty;
        }
    }
    // A beam's own neighbours leave it out.
    std::vector<BeamCrossing> near;
    const PhotonBeam& b0 = f.beams[0];
    plain.nearest(b0.origin, b0.dir, b0.length, 8, kInfinity, near, 0);
    for (const BeamCrossing& c : near) EXPECT_NE(c.index, 0u);
}

}  // namespace

// Whole beams, the automatic pieces, and pieces much shorter than the beams.
const double kPieces[] = {0.0, -1.0, 0.02};

double piece_length(const Field& f, double p) { return p < 0.0 ? PhotonBeamBvh::automatic_piece_length(f.beams) : p; }

TEST(PhotonBeamBvh, RandomRaysMatchBruteForce) {
    const Field f = make_field(3000, false, 11);
    for (const double p : kPieces) {
        const double piece = piece_length(f, p);
        const PhotonBeamBvh swept(f.beams, f.widths, piece), plain(f.beams, {}, piece);
        EXPECT_EQ(swept.size(), f.beams.size());
        if (p > 0.0) {
            EXPECT_GT(plain.item_count(), 5 * plain.size());
        } else if (p == 0.0) {
            EXPECT_EQ(plain.item_count(), plain.size());
        }
        Rng rng(12, 0);
        size_t crossed = 0, nonempty = 0;
        for (int r = 0; r < 200; ++r) {
            const Vec3 o(rng.uniform() * 1.4 - 0.2, rng.uniform() * 1.4 - 0.2, rng.uniform() * 1.4 - 0.2);
            const Vec3 d = sample_uniform_sphere(rng.uniform(), rng.uniform());
            const double tmax = r % 4 == 0 ? kInfinity : r % 4 == 1 ? 0.0 : 2.0 * rng.uniform();
            check_ray(f, swept, plain, o, d, tmax, crossed, nonempty);
        }
        EXPECT_GT(crossed, 200u);   // the test sees real crossings
        EXPECT_GT(nonempty, 500u);
    }
}

TEST(PhotonBeamBvh, AutomaticPiecesAreWithinTheMeanLength) {
    const Field f = make_field(3000, false, 11), flat = make_field(2000, true, 13);
    double mean = 0.0;
    for (const PhotonBeam& b : f.beams) mean += b.length / double(f.beams.size());
    const double piece = PhotonBeamBvh::automatic_piece_length(f.beams);
    EXPECT_GE(piece, mean / 8.0);
    EXPECT_LE(piece, mean * (1.0 + 1e-12));
    // A flat field (zero volume) takes the shortest pieces allowed, not zero-length ones.
    EXPECT_GT(PhotonBeamBvh::automatic_piece_length(flat.beams), 0.0);
    EXPECT_EQ(PhotonBeamBvh::automatic_piece_length({}), 0.0);
}

TEST(PhotonBeamBvh, KNearestTestsFewerBeamsWithPieces) {
    // The traversal's cost: long beams in a dense field (the furnace's case, docs/photon_beams.md)
    // test far fewer beams per k-nearest query with pieces, for the same answers.
    Rng rng(15, 0);
    std::vector<PhotonBeam> beams;
    for (int i = 0; i < 20000; ++i)
        beams.push_back({Vec3(rng.uniform(), rng.uniform(), rng.uniform()) * 4.0,
                         sample_uniform_sphere(rng.uniform(), rng.uniform()), 1.5 * rng.uniform(), Rgb::Ones()});
    const PhotonBeamBvh whole(beams, {}), pieces(beams, {}, PhotonBeamBvh::automatic_piece_length(beams));
    uint64_t tested_whole = 0, tested_pieces = 0;
    for (int q = 0; q < 50; ++q) {
        const Vec3 o = Vec3(1.0 + 2.0 * rng.uniform(), 1.0 + 2.0 * rng.uniform(), 1.0 + 2.0 * rng.uniform());
        const Vec3 d = sample_uniform_sphere(rng.uniform(), rng.uniform());
        std::vector<BeamCrossing> a, b;
        whole.nearest(o, d, 1.0, 8, kInfinity, a, UINT32_MAX, &tested_whole);
        pieces.nearest(o, d, 1.0, 8, kInfinity, b, UINT32_MAX, &tested_pieces);
        ASSERT_EQ(a.size(), b.size());
        for (size_t j = 0; j < a.size(); ++j) EXPECT_EQ(a[j].index, b[j].index);
    }
    std::printf("k = 8 nearest, 20000 beams: %.0f tests per query whole, %.0f with pieces of %.3f\n",
                double(tested_whole) / 50.0, double(tested_pieces) / 50.0, PhotonBeamBvh::automatic_piece_length(beams));
    EXPECT_LT(3 * tested_pieces, 2 * tested_whole);
}

TEST(PhotonBeamBvh, SegmentBoxMaxNormDistanceIsWhereTheGrownBoxIsFirstHit) {
    // The box grown by r on every side meets the segment exactly for r >= the distance: checked
    // by the slab test just below and just above it, on random boxes and segments, axis-parallel
    // and nearly axis-parallel directions, bounded and unbounded segments.
    Rng rng(16, 0);
    int hits_at_zero = 0, outside = 0;
    for (int i = 0; i < 20000; ++i) {
        const Vec3 lo(rng.uniform(), rng.uniform(), rng.uniform());
        const Bounds3 box{lo, lo + Vec3(rng.uniform(), rng.uniform(), rng.uniform()) * 0.5};
        Vec3 o = Vec3(rng.uniform(), rng.uniform(), rng.uniform()) * 3.0 - Vec3::Constant(1.0);
        if (i % 4 == 3) o = box.lo + 0.5 * (box.hi - box.lo);   // starting inside: distance 0
        Vec3 d = sample_uniform_sphere(rng.uniform(), rng.uniform());
        if (i % 5 == 1) d = Vec3::Unit(i % 3) * (i % 2 ? 1.0 : -1.0);
        if (i % 5 == 2) d = (Vec3::Unit(i % 3) + 1e-12 * d).normalized();
        const double tmax = i % 7 == 0 ? kInfinity : i % 7 == 1 ? 0.0 : 3.0 * rng.uniform();
        const double r = segment_box_distance_max_norm(box, o, d, tmax);
        ASSERT_GE(r, 0.0);
        ASSERT_TRUE(std::isfinite(r));
        auto grown_hit = [&](double g) {
            const Vec3 pad = Vec3::Constant(g);
            double t0, t1;
            return Bounds3{box.lo - pad, box.hi + pad}.intersect(Ray{o, d}, tmax, t0, t1);
        };
        const double eps = 1e-9 * (1.0 + r);
        EXPECT_TRUE(grown_hit(r + eps)) << i;
        if (r > eps) {
            EXPECT_FALSE(grown_hit(r - eps)) << i;
            ++outside;
        } else {
            ++hits_at_zero;
        }
        // A lower bound of the Euclidean distance: no point of the segment is nearer than r.
        for (double t : {0.0, 0.5, 1.0}) {
            const double tt = std::isfinite(tmax) ? t * tmax : t * 10.0;
            const Vec3 p = o + tt * d;
            const Vec3 q = p.cwiseMax(box.lo).cwiseMin(box.hi);
            EXPECT_LE(r, (p - q).norm() + 1e-12);
        }
    }
    EXPECT_GT(outside, 5000);
    EXPECT_GT(hits_at_zero, 5000);
}

TEST(PhotonBeamBvh, SlabFilterAndLineBoundHoldForEveryPointOfTheBox) {
    // The k-nearest query skips a box outside the slab 0 <= (x - o).d <= tmax and orders boxes by
    // at least their sphere distance to the line: both must hold for every point of the box (a
    // beam's foot may be anywhere in it). Random points of random boxes, against segments as above.
    Rng rng(17, 0);
    int skipped = 0, bounded = 0;
    for (int i = 0; i < 5000; ++i) {
        const Vec3 lo(rng.uniform(), rng.uniform(), rng.uniform());
        const Bounds3 box{lo, lo + Vec3(rng.uniform(), rng.uniform(), rng.uniform()) * 0.5};
        const Vec3 o = Vec3(rng.uniform(), rng.uniform(), rng.uniform()) * 3.0 - Vec3::Constant(1.0);
        Vec3 d = sample_uniform_sphere(rng.uniform(), rng.uniform());
        if (i % 5 == 1) d = Vec3::Unit(i % 3) * (i % 2 ? 1.0 : -1.0);
        const double tmax = i % 7 == 0 ? kInfinity : i % 7 == 1 ? 0.0 : 0.2 * rng.uniform();
        const bool meets = box_meets_segment_slab(box, o, d, tmax);
        const double line = box_line_distance_sphere(box, o, d);
        skipped += !meets;
        bounded += line > 0.0;
        for (int j = 0; j < 64; ++j) {
            const Vec3 x = box.lo + (box.hi - box.lo).cwiseProduct(Vec3(rng.uniform(), rng.uniform(), rng.uniform()));
            const double s = (x - o).dot(d);
            if (s >= 0.0 && s <= tmax) {
                ASSERT_TRUE(meets) << i;   // a point in the slab: the box meets it
            }
            ASSERT_LE(line, (x - o - s * d).norm() + 1e-12) << i;   // no point nearer the line than the bound
        }
    }
    EXPECT_GT(skipped, 1000);   // the filter does skip boxes, and the bound is not always 0
    EXPECT_GT(bounded, 1000);
}

TEST(PhotonBeamBvh, GrazingAxisParallelAndParallelRaysMatchBruteForce) {
    const Field f = make_field(2000, true, 13);
    for (const double p : kPieces) {
        const double piece = piece_length(f, p);
        const PhotonBeamBvh swept(f.beams, f.widths, piece), plain(f.beams, {}, piece);
        Rng rng(14, 0);
        size_t crossed = 0, nonempty = 0;
        for (int r = 0; r < 150; ++r) {
            Vec3 o(rng.uniform(), rng.uniform(), 0.5), d;
            switch (r % 5) {
                case 0:   // grazing the plane of beams, inside the widths' reach
                    o.z() = 0.5 + 0.04 * rng.uniform();
                    d = Vec3(rng.uniform() - 0.5, rng.uniform() - 0.5, 1e-9).normalized();
                    break;
                case 1:   // axis-parallel across the beams
                    o = Vec3(rng.uniform(), -0.1, 0.5 + 0.02 * (rng.uniform() - 0.5));
                    d = Vec3::UnitY();
                    break;
                case 2:   // parallel to half the beams (those along x: no crossing), across the rest
                    o.x() = -0.1;
                    d = Vec3::UnitX();
                    break;
                case 3:   // perpendicular to the plane
                    o.z() = -0.2;
                    d = Vec3::UnitZ();
                    break;
                default:  // within the plane, diagonal
                    d = Vec3(1.0, 1.0, 0.0).normalized();
                    o -= 0.5 * d;
                    break;
            }
            check_ray(f, swept, plain, o, d, r % 3 == 0 ? kInfinity : 1.5, crossed, nonempty);
        }
        EXPECT_GT(crossed, 50u);
        EXPECT_GT(nonempty, 300u);
    }
}

TEST(PhotonBeamBvh, CrossingGeometry) {
    // A beam along y through (0.5, 0, 0.2) and a camera ray along x from the origin: t* = 0.5,
    // v* = 0 - (-0) = the beam point nearest, u = 0.2, sin = 1.
    BeamCrossing c;
    ASSERT_TRUE(photon_beam_crossing(Vec3::Zero(), Vec3::UnitX(), 1.0, Vec3(0.5, -1.0, 0.2), Vec3::UnitY(), 2.0, c));
    EXPECT_NEAR(c.t, 0.5, 1e-15);
    EXPECT_NEAR(c.v, 1.0, 1e-15);
    EXPECT_NEAR(c.u, 0.2, 1e-15);
    EXPECT_NEAR(c.sin_theta, 1.0, 1e-15);
    EXPECT_FALSE(photon_beam_crossing(Vec3::Zero(), Vec3::UnitX(), 0.4, Vec3(0.5, -1.0, 0.2), Vec3::UnitY(), 2.0, c));   // t* > tmax
    EXPECT_FALSE(photon_beam_crossing(Vec3::Zero(), Vec3::UnitX(), 1.0, Vec3(0.5, -1.0, 0.2), Vec3::UnitY(), 0.9, c));   // v* > length
    EXPECT_FALSE(photon_beam_crossing(Vec3::Zero(), Vec3::UnitX(), 1.0, Vec3(0.0, 0.1, 0.0), Vec3::UnitX(), 2.0, c));    // parallel
    // 45 degrees: sin = 1/sqrt 2.
    ASSERT_TRUE(photon_beam_crossing(Vec3::Zero(), Vec3::UnitX(), 1.0, Vec3(0.0, -0.5, 0.1), Vec3(1, 1, 0).normalized(), 2.0, c));
    EXPECT_NEAR(c.sin_theta, std::sqrt(0.5), 1e-15);
    EXPECT_NEAR(c.u, 0.1, 1e-15);
    EXPECT_NEAR(c.t, 0.5, 1e-15);
}
