// BoxSilhouette: directions uniform over the solid angle a box covers, checked against a closed form
// and against rejection sampling of uniform directions (an estimator that shares nothing with it).
#include <gtest/gtest.h>

#include <cmath>

#include "core/sampling/rng.h"
#include "core/sampling/sampling.h"
#include "scene/lights/box_silhouette.h"

#include "support/light_from_config.h"

using namespace vpm;

namespace {

Bounds3 box_of(const Vec3& lo, const Vec3& hi) {
    Bounds3 b;
    b.extend(lo);
    b.extend(hi);
    return b;
}

bool hits(const Bounds3& box, const Vec3& from, const Vec3& dir, Vec3* where = nullptr) {
    double t0, t1;
    if (!box.intersect(Ray{from, dir}, kInfinity, t0, t1)) return false;
    if (where) *where = from + t0 * dir;
    return true;
}

// Statistics of a direction that lands on the box: which face it enters (one per axis) and where.
struct Landing {
    double face[3] = {0, 0, 0};
    double first_half = 0.0;   // entry point's x below the box's middle
};

Landing landing(const Bounds3& box, const Vec3& p) {
    Landing l;
    const Vec3 mid = 0.5 * (box.lo + box.hi);
    const Vec3 ext = box.hi - box.lo;
    int axis = 0;
    double best = kInfinity;
    for (int a = 0; a < 3; ++a) {   // the face the entry point lies on: nearest plane relative to the extent
        const double d = std::min(std::abs(p[a] - box.lo[a]), std::abs(p[a] - box.hi[a])) / ext[a];
        if (d < best) best = d, axis = a;
    }
    l.face[axis] = 1.0;
    l.first_half = p.x() < mid.x() ? 1.0 : 0.0;
    return l;
}

struct Tally {
    double n = 0, s[4] = {0, 0, 0, 0}, s2[4] = {0, 0, 0, 0};
    void add(const Landing& l) {
        const double v[4] = {l.face[0], l.face[1], l.face[2], l.first_half};
        n += 1;
        for (int i = 0; i < 4; ++i) s[i] += v[i], s2[i] += v[i] * v[i];
    }
    double mean(int i) const { return s[i] / n; }
    double var_of_mean(int i) const { return std::max(0.0, s2[i] / n - mean(i) * mean(i)) / n; }
};

}  // namespace

TEST(BoxSilhouette, SolidAngleOfAFaceOnAxisIsTheClosedForm) {
    // A 2a x 2b face seen from distance d on its axis covers 4 asin(a b / sqrt((a^2 + d^2)(b^2 + d^2))).
    const double a = 0.5, b = 1.5, d = 0.3;
    const Bounds3 box = box_of(Vec3(-a, -b, 0.0), Vec3(a, b, 0.0 + 4.0));
    const BoxSilhouette s(Vec3(0, 0, -d), box);
    ASSERT_TRUE(s.valid());
    const double exact = 4.0 * std::asin(a * b / std::sqrt((a * a + d * d) * (b * b + d * d)));
    EXPECT_NEAR(s.solid_angle(), exact, 1e-12);
    // The same configuration a million units from the origin keeps its digits (all but those the
    // coordinates themselves lose: an ulp of 3e6 is 5e-10 against d = 0.3).
    const Vec3 far(1e6, -2e6, 3e6);
    const Bounds3 moved = box_of(box.lo + far, box.hi + far);
    EXPECT_NEAR(BoxSilhouette(Vec3(0, 0, -d) + far, moved).solid_angle(), exact, 1e-8);
}

TEST(BoxSilhouette, InsideEmptyOrSpeckIsNotValid) {
    const Bounds3 box = box_of(Vec3(0, 0, 0), Vec3(1, 2, 3));
    EXPECT_FALSE(BoxSilhouette(Vec3(0.5, 1, 1), box).valid());   // inside
    EXPECT_FALSE(BoxSilhouette(Vec3(5, 5, 5), Bounds3{}).valid());   // empty box
    EXPECT_FALSE(BoxSilhouette(Vec3(1e5, 0, 0), box).valid());   // 6 / 1e10 sr: below kMinSolidAngle
    EXPECT_TRUE(BoxSilhouette(Vec3(1e2, 0, 0), box).valid());
}

TEST(BoxSilhouette, DirectionsAreUniformOverTheSilhouette) {
    // Viewpoints near a face, near an edge, off a corner, and far: (1) the solid angle agrees with the
    // fraction of uniform directions that meet the box, (2) every sampled direction meets the box,
    // (3) the share of directions entering each face and the share landing on the box's lower x half
    // agree with those of the uniform directions that meet it, within 4 standard errors.
    const Bounds3 box = box_of(Vec3(-1, -0.5, -0.25), Vec3(1, 0.5, 0.25));
    const Vec3 views[] = {Vec3(0.2, 0.1, 0.4), Vec3(1.3, 0.7, 0.0), Vec3(-1.6, -0.9, 0.8), Vec3(4.0, 6.0, -5.0)};
    uint64_t seed = 100;
    for (const Vec3& from : views) {
        SCOPED_TRACE(testing::Message() << "from " << from.transpose());
        const BoxSilhouette sil(from, box);
        ASSERT_TRUE(sil.valid());
        Rng rng(++seed, 1);
        Tally uniform, sampled;
        const int n = 400000;
        for (int i = 0; i < n; ++i) {
            const Vec3 w = sample_uniform_sphere(rng.uniform(), rng.uniform());
            Vec3 p;
            if (hits(box, from, w, &p)) uniform.add(landing(box, p));
        }
        const double share = uniform.n / n;
        const double se_share = std::sqrt(share * (1 - share) / n);
        EXPECT_NEAR(sil.solid_angle(), 4.0 * kPi * share, 4.0 * 4.0 * kPi * se_share);
        int missed = 0;
        for (int i = 0; i < n / 4; ++i) {
            const double u0 = rng.uniform(), u1 = rng.uniform(), u2 = rng.uniform();
            const Vec3 w = sil.sample(u0, u1, u2);
            Vec3 p;
            if (!hits(box, from, w, &p)) ++missed;
            else sampled.add(landing(box, p));
        }
        EXPECT_EQ(missed, 0);
        for (int k = 0; k < 4; ++k)
            EXPECT_NEAR(sampled.mean(k), uniform.mean(k), 4.0 * std::sqrt(sampled.var_of_mean(k) + uniform.var_of_mean(k)) + 1e-12)
                << "statistic " << k;
    }
}

TEST(BoxSilhouette, PointLightEmitsOverTheSilhouetteWithItsPower) {
    // A point light just above a box (inside the box's bounding sphere, where the cone would be the
    // whole sphere): power I times the silhouette's solid angle, and every photon meets the box.
    const Bounds3 box = box_of(Vec3(-1, -1, -1), Vec3(1, 1, 1));
    auto light = test::light_from("[[lights]]\ntype='point'\nposition=[0.3,1.4,0.2]\nintensity=3\n");
    light->set_scene_bounds(box);
    const BoxSilhouette sil(Vec3(0.3, 1.4, 0.2), box);
    EXPECT_NEAR(light->power()[0], 3.0 * sil.solid_angle(), 1e-12);
    EXPECT_LT(sil.solid_angle(), 2.0 * kPi);   // a face and a half at most from there, not the sphere
    Rng rng(7, 2);
    int missed = 0;
    for (int i = 0; i < 20000; ++i) {
        const EmissionSample e = light->sample_emission(rng);
        missed += !hits(box, e.ray.origin, e.ray.dir);
        ASSERT_EQ(e.power[0], light->power()[0]);
    }
    EXPECT_EQ(missed, 0);
}
