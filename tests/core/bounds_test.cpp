// Bounds3 (core/math.h): the slab test's interval, and an empty box missed by every ray.
#include <gtest/gtest.h>

#include "core/math.h"

using namespace vpm;

TEST(Bounds3, SlabTestGivesTheIntervalInsideTheBoxClippedToTmax) {
    Bounds3 box;
    box.extend(Vec3(-1, -1, -1));
    box.extend(Vec3(1, 1, 1));
    double t0 = 0, t1 = 0;
    ASSERT_TRUE(box.intersect(Ray{Vec3(0, 0, -3), Vec3(0, 0, 1)}, 10.0, t0, t1));
    EXPECT_DOUBLE_EQ(t0, 2.0);
    EXPECT_DOUBLE_EQ(t1, 4.0);
    ASSERT_TRUE(box.intersect(Ray{Vec3(0, 0, -3), Vec3(0, 0, 1)}, 3.0, t0, t1));
    EXPECT_DOUBLE_EQ(t1, 3.0);
    EXPECT_FALSE(box.intersect(Ray{Vec3(0, 0, -3), Vec3(0, 0, -1)}, 10.0, t0, t1));
}

// An empty box's slabs (lo = +inf, hi = -inf) swap into the whole line on every axis; a box of no
// media must not clip a photon's flight into a beam.
TEST(Bounds3, AnEmptyBoxIsMissedByEveryRay) {
    const Bounds3 empty;
    ASSERT_TRUE(empty.empty());
    double t0 = 0, t1 = 0;
    for (const Vec3& d : {Vec3(0, 0, 1), Vec3(1, 1, 1).normalized(), Vec3(-0.3, 0.9, 0.1).normalized()})
        EXPECT_FALSE(empty.intersect(Ray{Vec3(0.5, -2, 7), d}, kInfinity, t0, t1));
}
