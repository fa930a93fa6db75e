// A medium confined to a closed glass shape (`interior_medium = N`, scene/interior_medium.h): its
// extinction is the medium's inside the shape and 0 everywhere else, for spheres and meshes, along
// rays that start outside, inside or on the surface; the key's bad values are one error each.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "core/error.h"
#include "core/sampling/rng.h"
#include "scene/interior_medium.h"
#include "support/scene_from_config.h"
#include "support/scratch_dir.h"

using namespace vpm;

namespace {

const char* kLight = R"(
[camera]
position = [0, 0, 5]
look_at = [0, 0, 0]
[[lights]]
type = "environment"
radiance = 1.0
)";

// A homogeneous medium table of extinction sigma filling a sphere of radius 1.5 around the origin.
std::string fog(double sigma) {
    return "[[media]]\ntype = \"homogeneous\"\nshape = \"sphere\"\nradius = 1.5\nsigma_t_scale = " + std::to_string(sigma) +
           "\nalbedo = 0.8\ng = 0.3\n";
}

const char* kGlassSphere = R"(
[[shapes]]
type = "sphere"
center = [0, 0, 0]
radius = 1.0
material = "dielectric"
ior = 1.5
interior_medium = 0
)";

const char* kGlassBox = R"(
[[shapes]]
type = "box"
min = [-0.5, -0.5, -0.5]
max = [0.5, 0.5, 0.5]
material = "dielectric"
ior = 1.5
interior_medium = 0
)";

std::string build_error(const std::string& text) {
    try {
        test::scene_from_config(text);
    } catch (const ConfigError& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST(InteriorMedium, SphereHoldsTheMediumAndNothingOutsideSeesIt) {
    const auto scene = test::scene_from_config(std::string(kLight) + fog(2.0) + kGlassSphere);
    ASSERT_EQ(scene->media.size(), 1u);
    const Medium& m = *scene->media[0];
    EXPECT_EQ(m.interior_of(), 0);
    EXPECT_DOUBLE_EQ(m.albedo().x(), 0.8);
    EXPECT_DOUBLE_EQ(m.g(), 0.3);
    EXPECT_EQ(m.sigma_t(Vec3(0, 0, 0)), 2.0);
    EXPECT_EQ(m.sigma_t(Vec3(0, 1.2, 0)), 0.0);   // inside the medium's table, outside the glass
    EXPECT_NEAR(m.bounds().hi.x(), 1.0, 1e-15);    // the glass, not the table's 1.5
    // Through the centre: the chord of the glass (2), not of the table's sphere (3).
    const Ray through{Vec3(0, 0, 5), Vec3(0, 0, -1)};
    EXPECT_NEAR(scene->optical_depth(through, kInfinity), 4.0, 1e-12);
    Rng rng(7);
    EXPECT_NEAR(m.transmittance(through, kInfinity, rng), std::exp(-4.0), 1e-15);
    // From inside the glass and from its surface.
    EXPECT_NEAR(scene->optical_depth(Ray{Vec3(0, 0, 0.25), Vec3(0, 0, 1)}, kInfinity), 1.5, 1e-12);
    EXPECT_NEAR(scene->optical_depth(Ray{Vec3(0, 0, 1), Vec3(0, 0, -1)}, 1.5), 3.0, 1e-12);
    EXPECT_NEAR(scene->optical_depth(Ray{Vec3(0, 0, 1), Vec3(0, 0, 1)}, kInfinity), 0.0, 1e-12);
    // A ray that misses the glass but crosses the table's sphere: no extinction, no collision.
    const Ray missing{Vec3(0, 1.2, 5), Vec3(0, 0, -1)};
    EXPECT_EQ(scene->optical_depth(missing, kInfinity), 0.0);
    EXPECT_EQ(scene->transmittance(missing, 10.0, rng), 1.0);
    for (int i = 0; i < 10000; ++i) ASSERT_FALSE(scene->sample_medium(missing, kInfinity, rng)) << i;
    // Free flights through the centre: collisions only inside the glass, as often as 1 - exp(-4).
    const int n = 40000;
    int collided = 0;
    for (int i = 0; i < n; ++i) {
        const MediumEvent e = scene->sample_medium(through, kInfinity, rng);
        if (!e) continue;
        ++collided;
        ASSERT_GE(e.t, 4.0);
        ASSERT_LE(e.t, 6.0);
    }
    const double p = 1.0 - std::exp(-4.0), se = std::sqrt(p * (1 - p) / n);
    EXPECT_NEAR(double(collided) / n, p, 3.0 * se);
    // Majorant pieces and the optical-depth profile cover the chord alone.
    double majorant = 0.0;
    m.majorant_pieces(through, kInfinity, [&](double ta, double tb, double mj) {
        EXPECT_GE(ta, 4.0 - 1e-12);
        EXPECT_LE(tb, 6.0 + 1e-12);
        majorant += mj * (tb - ta);
        return true;
    });
    EXPECT_NEAR(majorant, 4.0, 1e-12);
    OpticalDepthProfile profile;
    m.optical_depth_profile(through, kInfinity, profile);
    EXPECT_NEAR(profile.total(), 4.0, 1e-12);
    size_t cursor = 0;
    EXPECT_NEAR(profile.invert(2.0, cursor), 5.0, 1e-12);
}

TEST(InteriorMedium, BallIntegralsAreClippedToTheGlass) {
    const auto scene = test::scene_from_config(std::string(kLight) + fog(2.0) + kGlassSphere);
    const Medium& m = *scene->media[0];
    double in = 0.0;
    ASSERT_TRUE(m.ball_integral(Vec3(0.2, 0, 0), 0.3, in));   // wholly inside
    EXPECT_NEAR(in, 2.0 * 4.0 / 3.0 * kPi * 0.027, 1e-12);
    ASSERT_TRUE(m.ball_integral(Vec3(1.3, 0, 0), 0.2, in));   // wholly outside, inside the table's sphere
    EXPECT_EQ(in, 0.0);
    // Crossing the glass: the lens of the two balls (centres d apart, radii r and R = 1).
    const double d = 0.95, r = 0.2, R = 1.0;
    const double lens = kPi * (R + r - d) * (R + r - d) * (d * d + 2 * d * r - 3 * r * r + 2 * d * R + 6 * r * R - 3 * R * R) / (12 * d);
    ASSERT_TRUE(m.ball_integral(Vec3(d, 0, 0), r, in));
    EXPECT_NEAR(in, 2.0 * lens, 1e-12);
}

TEST(InteriorMedium, MeshHoldsTheMediumByParity) {
    const auto scene = test::scene_from_config(std::string(kLight) + fog(1.0) + kGlassBox);
    const Medium& m = *scene->media[0];
    EXPECT_EQ(m.sigma_t(Vec3(0.1, 0.2, 0.3)), 1.0);
    EXPECT_EQ(m.sigma_t(Vec3(0.7, 0.2, 0.3)), 0.0);
    EXPECT_NEAR(scene->optical_depth(Ray{Vec3(0.1, 0.2, 5), Vec3(0, 0, -1)}, kInfinity), 1.0, 1e-9);
    EXPECT_NEAR(scene->optical_depth(Ray{Vec3(0.1, 0.2, 0), Vec3(0, 0, 1)}, kInfinity), 0.5, 1e-9);
    EXPECT_NEAR(scene->optical_depth(Ray{Vec3(0.1, 0.2, 0.5), Vec3(0, 0, -1)}, kInfinity), 1.0, 1e-9);   // on the face
    EXPECT_NEAR(scene->optical_depth(Ray{Vec3(0.1, 0.2, 5), Vec3(0, 0, -1)}, 4.75), 0.25, 1e-9);         // stops inside
    EXPECT_EQ(scene->optical_depth(Ray{Vec3(0.7, 0.2, 5), Vec3(0, 0, -1)}, kInfinity), 0.0);
}

TEST(InteriorMedium, MeshBallIntegralsCountThePartInside) {
    const auto scene = test::scene_from_config(std::string(kLight) + fog(2.0) + kGlassBox);
    const Medium& m = *scene->media[0];
    const double r = 0.1, ball = 4.0 / 3.0 * kPi * r * r * r;
    double in = 0.0;
    ASSERT_TRUE(m.ball_integral(Vec3(0.1, 0, 0), r, in));   // wholly inside the box: every point counts
    EXPECT_NEAR(in, 2.0 * ball, 1e-12);
    double m0 = 0.0;
    Vec3 m1;
    Eigen::Matrix3d m2;
    ASSERT_TRUE(m.ball_moments(Vec3(0.1, 0, 0), r, m0, m1, m2));
    EXPECT_EQ(m1, Vec3::Zero());   // centre-symmetric points
    // Through a face: the ball less its cap beyond x = 0.5 (height 0.05), to the 256 points' resolution
    // (BallFractionIsTheLensVolumeAndItsQuadrature: about 1% of the ball).
    const double h = 0.05, cap = kPi * h * h * (3 * r - h) / 3.0;
    ASSERT_TRUE(m.ball_integral(Vec3(0.45, 0, 0), r, in));
    EXPECT_NEAR(in / (2.0 * ball), 1.0 - cap / ball, 0.02);
    ASSERT_TRUE(m.ball_moments(Vec3(0.45, 0, 0), r, m0, m1, m2));
    EXPECT_DOUBLE_EQ(m0, in);
    EXPECT_LT(m1.x(), 0.0);   // the part inside lies towards -x
}

TEST(InteriorMedium, BadKeysAreOneErrorEach) {
    const std::string glass = kGlassSphere;
    // Not a [[media]] table: the error names the key and the allowed indices.
    std::string e = build_error(std::string(kLight) + fog(1.0) + std::string(glass).replace(glass.find("= 0"), 3, "= 1"));
    EXPECT_NE(e.find("shapes.0.interior_medium"), std::string::npos) << e;
    EXPECT_NE(e.find("allowed: 0 to 0"), std::string::npos) << e;
    e = build_error(std::string(kLight) + glass);
    EXPECT_NE(e.find("no [[media]]"), std::string::npos) << e;
    e = build_error(std::string(kLight) + fog(1.0) + std::string(glass).replace(glass.find("= 0"), 3, "= -1"));
    EXPECT_NE(e.find("interior_medium"), std::string::npos) << e;
    // Not a closed glass shape.
    std::string opaque = glass;
    opaque.replace(opaque.find("material = \"dielectric\""), 23, "material = \"lambertian\"");
    opaque.replace(opaque.find("ior = 1.5\n"), 10, "");
    e = build_error(std::string(kLight) + fog(1.0) + opaque);
    EXPECT_NE(e.find("shapes.0.interior_medium"), std::string::npos) << e;
    EXPECT_NE(e.find("dielectric"), std::string::npos) << e;
    // Two shapes naming the same medium.
    e = build_error(std::string(kLight) + fog(1.0) + glass + std::string(kGlassBox));
    EXPECT_NE(e.find("shapes.1.interior_medium"), std::string::npos) << e;
    EXPECT_NE(e.find("already the interior medium of shape 0"), std::string::npos) << e;
}

// A mesh crossed more often along one ray than the interval buffer holds is refused with one error,
// not written past the buffer: 33 closed cubes in a row along x (the camera looks across the row)
// as one glass shape. From inside the first cube 65 crossings lie ahead (33 intervals inside); from
// inside the third 61 (31), which are counted.
TEST(InteriorMedium, AMeshCrossedTooOftenIsRefused) {
    test::ScratchDir dir;
    const std::filesystem::path obj = dir.path / "row.obj";
    {
        std::ofstream out(obj);
        for (int c = 0; c < 33; ++c) {
            const double x0 = 0.1 * c, x1 = x0 + 0.05;
            for (int v = 0; v < 8; ++v)
                out << "v " << ((v & 1) ? x1 : x0) << " " << ((v & 2) ? 0.5 : -0.5) << " " << ((v & 4) ? 0.5 : -0.5) << "\n";
            const int b = 8 * c + 1;   // the cube's faces, wound outwards
            const int f[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
            for (const auto& q : f) out << "f " << b + q[0] << " " << b + q[1] << " " << b + q[2] << " " << b + q[3] << "\n";
        }
    }
    const std::string glass = "[[shapes]]\ntype = \"mesh\"\nfile = \"" + obj.string() +
                              "\"\nmaterial = \"dielectric\"\nior = 1.5\ninterior_medium = 0\n";
    const auto scene = test::scene_from_config(std::string(kLight) + fog(1.0) + glass);
    const Medium& m = *scene->media[0];
    EXPECT_EQ(m.sigma_t(Vec3(0.025, 0.2, 0.1)), 1.0);
    Rng rng(1, 0);
    EXPECT_THROW(m.transmittance(Ray{Vec3(0.025, 0.2, 0.1), Vec3(1, 0, 0)}, kInfinity, rng), Error);
    // The fog table is a ball of radius 1.5 (at y 0.2, z 0.1 it ends at x 1.4832): from x 0.225 the
    // rest of the third cube and cubes 3 to 14.
    EXPECT_NEAR(scene->optical_depth(Ray{Vec3(0.225, 0.2, 0.1), Vec3(1, 0, 0)}, kInfinity), 0.025 + 12 * 0.05, 1e-9);
}

