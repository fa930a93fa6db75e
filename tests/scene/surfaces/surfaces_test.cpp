// Embree-backed surfaces: configuration keys, materials, and ray queries against analytic answers.
#include <gtest/gtest.h>

#include <cctype>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <thread>

#include "core/error.h"
#include "scene/materials/material.h"
#include "scene/surfaces/surfaces.h"
#include "support/scratch_dir.h"

namespace fs = std::filesystem;
using namespace vpm;

namespace {

// Builds surfaces from the [[shapes]] of a TOML text; relative paths resolve from `base`.
std::unique_ptr<Surfaces> build(const std::string& toml, const fs::path& base = VPM_TEST_DATA_DIR) {
    auto doc = parse_config(toml, "test.toml", base);
    toml::table resolved;
    Params root(doc, &resolved);
    std::vector<Params> shapes = root.tables("shapes");
    return Surfaces::create(shapes);
}

std::string config_error(const std::string& toml) {
    try {
        build(toml);
    } catch (const ConfigError& e) {
        return e.what();
    }
    return "(no ConfigError)";
}

Ray ray(const Vec3& o, const Vec3& d) { return Ray{o, d.normalized()}; }

Vec3 random_dir(std::mt19937_64& rng) {
    std::normal_distribution<double> n;
    Vec3 d(n(rng), n(rng), n(rng));
    return d.normalized();
}

}  // namespace

TEST(Surfaces, QuadHitDistanceAndNormalFacingTheRay) {
    auto s = build("[[shapes]]\ntype = 'quad'\ncenter = [0, 0, 1]\nu = [2, 0, 0]\nv = [0, 1, 0]\n");
    EXPECT_EQ(s->triangle_count(), 2u);
    EXPECT_TRUE(s->bounds().lo.isApprox(Vec3(-2, -1, 1)));
    EXPECT_TRUE(s->bounds().hi.isApprox(Vec3(2, 1, 1)));
    SurfaceHit h;
    ASSERT_TRUE(s->intersect(ray({1.9, 0.3, 6}, {0, 0, -1}), kInfinity, h));
    EXPECT_NEAR(h.t, 5.0, 1e-12);
    EXPECT_TRUE(h.position.isApprox(Vec3(1.9, 0.3, 1), 1e-12));
    EXPECT_TRUE(h.normal.isApprox(Vec3(0, 0, 1), 1e-12));
    EXPECT_TRUE(h.reflectance.isApprox(Rgb::Constant(0.5)));   // default material
    ASSERT_TRUE(s->intersect(ray({-1.5, -0.9, -2}, {0, 0, 1}), kInfinity, h));
    EXPECT_NEAR(h.t, 3.0, 1e-12);
    EXPECT_TRUE(h.normal.isApprox(Vec3(0, 0, -1), 1e-12));
    EXPECT_FALSE(s->intersect(ray({2.1, 0, 6}, {0, 0, -1}), kInfinity, h));   // beyond the u half-edge
    EXPECT_FALSE(s->intersect(ray({0, 1.1, 6}, {0, 0, -1}), kInfinity, h));   // beyond the v half-edge
    EXPECT_FALSE(s->intersect(ray({0, 0, 6}, {0, 0, -1}), 4.99, h));          // tmax before the hit
    EXPECT_FALSE(s->occluded(ray({0, 0, 6}, {0, 0, -1}), 4.99));
    EXPECT_TRUE(s->occluded(ray({0, 0, 6}, {0, 0, -1}), 5.01));
    EXPECT_FALSE(s->intersect(ray({0, 0, 6}, {0, 0, 1}), kInfinity, h));      // pointing away
}

TEST(Surfaces, RaysFromFarAwayStillHit) {
    // Origins 1e30 away (photons around a medium of 1e32 units, issue 12) are beyond Embree's
    // float range; they are advanced to the surfaces' bounds in double first.
    auto s = build("[[shapes]]\ntype = 'quad'\ncenter = [0, 0, 1]\nu = [2, 0, 0]\nv = [0, 1, 0]\n");
    SurfaceHit h;
    for (const double far : {1e7, 1e20, 1e30}) {
        ASSERT_TRUE(s->intersect(ray({1.5, 0.25, 1 + far}, {0, 0, -1}), kInfinity, h)) << far;
        EXPECT_NEAR(h.t, far, 1e-12 * far);
        EXPECT_TRUE(h.position.isApprox(Vec3(1.5, 0.25, 1), 1e-9)) << h.position.transpose();
        EXPECT_TRUE(s->occluded(ray({1.5, 0.25, 1 + far}, {0, 0, -1}), 2 * far));
        EXPECT_FALSE(s->occluded(ray({1.5, 0.25, 1 + far}, {0, 0, -1}), 0.5 * far));
        EXPECT_FALSE(s->intersect(ray({3.0, 0.25, 1 + far}, {0, 0, -1}), kInfinity, h));   // beside the quad
        EXPECT_FALSE(s->intersect(ray({1.5, 0.25, 1 + far}, {0, 0, 1}), kInfinity, h));    // pointing away
    }
}

TEST(Surfaces, TransformScaleRotateTranslateInThatOrder) {
    // Unit quad in xy, scaled x2 in x, rotated +90 deg about x (y -> z), moved by (0, 5, 0).
    auto s = build("[[shapes]]\ntype = 'quad'\ncenter = [0, 0, 0]\nu = [1, 0, 0]\nv = [0, 1, 0]\n"
                   "transform = { scale = [2, 1, 1], rotate = [1, 0, 0, 90], translate = [0, 5, 0] }\n");
    EXPECT_TRUE(s->bounds().lo.isApprox(Vec3(-2, 5, -1), 1e-12)) << s->bounds().lo.transpose();
    EXPECT_TRUE(s->bounds().hi.isApprox(Vec3(2, 5, 1), 1e-12)) << s->bounds().hi.transpose();
    SurfaceHit h;
    ASSERT_TRUE(s->intersect(ray({1.8, 0, 0.9}, {0, 1, 0}), kInfinity, h));
    EXPECT_NEAR(h.t, 5.0, 1e-12);
    EXPECT_TRUE(h.normal.isApprox(Vec3(0, -1, 0), 1e-12));
    EXPECT_FALSE(s->intersect(ray({2.1, 0, 0}, {0, 1, 0}), kInfinity, h));
}

TEST(Surfaces, BoxAxisRaysFromOutsideAndInside) {
    auto s = build("[[shapes]]\ntype = 'box'\nmin = [-1, -2, -3]\nmax = [1, 2, 3]\n");
    EXPECT_EQ(s->triangle_count(), 12u);
    const Vec3 hi(1, 2, 3);
    SurfaceHit h;
    for (int a = 0; a < 3; ++a)
        for (double sign : {-1.0, 1.0}) {
            Vec3 dir = Vec3::Zero();
            dir[a] = sign;
            Vec3 o = Vec3(0.1, 0.2, 0.3) - 10.0 * dir;   // outside, heading in along +-axis a
            ASSERT_TRUE(s->intersect(Ray{o, dir}, kInfinity, h));
            EXPECT_NEAR(h.t, 10.0 + (sign > 0 ? -0.1 * (a == 0) - 0.2 * (a == 1) - 0.3 * (a == 2)
                                               : 0.1 * (a == 0) + 0.2 * (a == 1) + 0.3 * (a == 2)) - hi[a], 1e-12);
            EXPECT_TRUE(h.normal.isApprox(-dir, 1e-12));
            ASSERT_TRUE(s->intersect(Ray{Vec3::Zero(), dir}, kInfinity, h));   // from inside: the exit wall
            EXPECT_NEAR(h.t, hi[a], 1e-12);
            EXPECT_TRUE(h.normal.isApprox(-dir, 1e-12));   // faces the ray, i.e. inward
        }
}

TEST(Surfaces, RandomRaysAgreeWithAnalyticBox) {
    // Box scaled and moved far from the origin: float Embree, double answers.
    for (double far : {0.0, 1e6}) {
        const std::string t = std::to_string(far);
        auto s = build("[[shapes]]\ntype = 'box'\nmin = [0, 0, 0]\nmax = [1, 1, 1]\n"
                       "transform = { scale = [2, 3, 4], translate = [" + t + ", -5, " + t + "] }\n");
        const Bounds3 box{Vec3(far, -5, far), Vec3(far + 2, -2, far + 4)};
        std::mt19937_64 rng(7);
        std::uniform_real_distribution<double> u(-2, 6);
        int hits = 0, mismatches = 0;
        const int n = 20000;
        for (int i = 0; i < n; ++i) {
            const Ray r{Vec3(far + u(rng), -5 + u(rng), far + u(rng)), random_dir(rng)};
            const double tmax = i % 4 == 0 ? 3.0 : kInfinity;
            double t0, t1;
            const bool inside = box.contains(r.origin);
            bool expect = box.intersect(r, tmax, t0, t1);
            const double t_ref = inside ? t1 : t0;
            if (expect && inside && t1 >= tmax) expect = false;   // exit wall beyond tmax
            SurfaceHit h;
            const bool got = s->intersect(r, tmax, h);
            EXPECT_EQ(got, s->occluded(r, tmax));
            if (got != expect) { ++mismatches; continue; }   // only at edges / grazing, counted below
            if (!got) continue;
            ++hits;
            EXPECT_NEAR(h.t, t_ref, 1e-9 * (1 + far)) << "ray " << i;
            EXPECT_LT(h.normal.dot(r.dir), 0.0);
            EXPECT_NEAR(h.normal.cwiseAbs().maxCoeff(), 1.0, 1e-12);
            EXPECT_TRUE((h.position - r.at(h.t)).norm() < 1e-9 * (1 + far));
        }
        EXPECT_GT(hits, n / 10);
        EXPECT_LE(mismatches, n / 2000) << "far = " << far;
    }
}

TEST(Surfaces, RaysStartingOnTheSurfaceDoNotHitTheirStart) {
    auto s = build("[[shapes]]\ntype = 'box'\nmin = [-1, -1, -1]\nmax = [1, 1, 1]\n"
                   "transform = { rotate = [1, 2, 3, 37], translate = [3, -2, 100] }\n");
    // Points on the box in object space, moved like the config does (a rigid motion keeps
    // distances). Rays leaving outward never hit the box, grazing ones included; rays going
    // inward hit where the analytic box says they leave it.
    Eigen::Affine3d m = Eigen::Affine3d::Identity();
    m.translate(Vec3(3, -2, 100));
    m.rotate(Eigen::AngleAxisd(37 * kPi / 180, Vec3(1, 2, 3).normalized()));
    const Bounds3 box{Vec3::Constant(-1), Vec3::Constant(1)};
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> u(-1, 1);
    int self_hits = 0, edge_skims = 0, inward_wrong = 0, grazing = 0;
    for (int i = 0; i < 20000; ++i) {
        Vec3 p(u(rng), u(rng), u(rng));
        const int a = i % 3;
        p[a] = (i / 3) % 2 ? 1.0 : -1.0;
        Vec3 n = Vec3::Zero();
        n[a] = p[a];
        Vec3 d = random_dir(rng);
        if (i % 2) d = (d - (d.dot(n) + 1e-3 * u(rng)) * n).normalized();   // half of them grazing
        if (d.dot(n) < 0) d = -d;
        grazing += d.dot(n) < 1e-3;
        SurfaceHit h;
        const bool out_hit = s->intersect(Ray{m * p, m.linear() * d}, kInfinity, h);
        EXPECT_EQ(out_hit, s->occluded(Ray{m * p, m.linear() * d}, kInfinity));
        if (out_hit) {
            // Only a ray skimming within float precision past an edge of the adjacent face may hit.
            const Vec3 q = m.inverse() * h.position;
            const double outside = (q.cwiseAbs() - Vec3::Ones()).maxCoeff();
            if (outside > 1e-6) ++self_hits;
            else ++edge_skims;
        }
        double t0, t1;
        ASSERT_TRUE(box.intersect(Ray{p, -d}, kInfinity, t0, t1));
        const bool got = s->intersect(Ray{m * p, m.linear() * -d}, kInfinity, h);
        EXPECT_EQ(got, s->occluded(Ray{m * p, m.linear() * -d}, kInfinity));
        if (t1 > 1e-3 && (!got || std::abs(h.t - t1) > 1e-9)) ++inward_wrong;
    }
    EXPECT_GT(grazing, 5000);
    EXPECT_EQ(self_hits, 0);
    EXPECT_LE(edge_skims, 20);
    EXPECT_LE(inward_wrong, 2);   // a ray grazing an edge may slip through it
}

TEST(Surfaces, MeshFromObjRelativeToTheConfig) {
    auto s = build("[[shapes]]\ntype = 'mesh'\nfile = 'tetra.obj'\nreflectance = [0.2, 0.4, 0.6]\n");
    EXPECT_EQ(s->triangle_count(), 4u);
    SurfaceHit h;
    ASSERT_TRUE(s->intersect(ray({0.2, 0.2, -1}, {0, 0, 1}), kInfinity, h));
    EXPECT_NEAR(h.t, 1.0, 1e-12);
    EXPECT_TRUE(h.normal.isApprox(Vec3(0, 0, -1), 1e-12));
    EXPECT_TRUE(h.reflectance.isApprox(Rgb(0.2, 0.4, 0.6)));
    ASSERT_TRUE(s->intersect(ray({1, 1, 1}, {-1, -1, -1}), kInfinity, h));
    EXPECT_NEAR(h.t, 2.0 / std::sqrt(3.0), 1e-12);
    EXPECT_TRUE(h.normal.isApprox(Vec3(1, 1, 1).normalized(), 1e-12));
    EXPECT_TRUE(h.position.isApprox(Vec3::Constant(1.0 / 3.0), 1e-12));
}

TEST(Surfaces, MeshFromPlyInAnotherFolder) {
    const vpm::test::ScratchDir scratch;
    const fs::path& dir = scratch.path;
    std::ofstream(dir / "tri.ply") << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                                      "property float y\nproperty float z\nelement face 1\n"
                                      "property list uchar int vertex_indices\nend_header\n"
                                      "0 0 2\n1 0 2\n0 1 2\n3 0 1 2\n";
    auto s = build("[[shapes]]\ntype = 'mesh'\nfile = 'tri.ply'\nmaterial = 'black'\n", dir);
    SurfaceHit h;
    ASSERT_TRUE(s->intersect(ray({0.25, 0.25, 0}, {0, 0, 1}), kInfinity, h));
    EXPECT_NEAR(h.t, 2.0, 1e-12);
    EXPECT_TRUE(h.reflectance.isApprox(Rgb::Zero()));
    std::ofstream(dir / "bad.ply") << "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"
                                      "property float y\nproperty float z\nelement face 1\n"
                                      "property list uchar int vertex_indices\nend_header\n0 0 0\n3 0 1 2\n";
    EXPECT_THROW(build("[[shapes]]\ntype = 'mesh'\nfile = 'bad.ply'\n", dir), FileError);
}

TEST(Surfaces, MaterialPerShapeAndClosestHit) {
    auto s = build("[[shapes]]\ntype = 'quad'\ncenter = [0, 0, 1]\nu = [1, 0, 0]\nv = [0, 1, 0]\nmaterial = 'black'\n"
                   "[[shapes]]\ntype = 'quad'\ncenter = [0, 0, 2]\nu = [1, 0, 0]\nv = [0, 1, 0]\nreflectance = 0.8\n"
                   "[[shapes]]\ntype = 'box'\nmin = [-1, -1, 3]\nmax = [1, 1, 4]\nreflectance = [1, 0, 0.25]\n");
    SurfaceHit h;
    ASSERT_TRUE(s->intersect(ray({0, 0, 0}, {0, 0, 1}), kInfinity, h));
    EXPECT_NEAR(h.t, 1.0, 1e-12);
    EXPECT_TRUE(h.reflectance.isApprox(Rgb::Zero()));
    ASSERT_TRUE(s->intersect(ray({0, 0, 1.5}, {0, 0, 1}), kInfinity, h));
    EXPECT_NEAR(h.t, 0.5, 1e-12);
    EXPECT_TRUE(h.reflectance.isApprox(Rgb::Constant(0.8)));
    ASSERT_TRUE(s->intersect(ray({0, 0, 2.5}, {0, 0, 1}), kInfinity, h));
    EXPECT_NEAR(h.t, 0.5, 1e-12);
    EXPECT_TRUE(h.reflectance.isApprox(Rgb(1, 0, 0.25)));
    const std::string d = s->describe();
    EXPECT_NE(d.find("3 shapes"), std::string::npos) << d;
    EXPECT_NE(d.find("1 box"), std::string::npos) << d;
    EXPECT_NE(d.find("2 quad"), std::string::npos) << d;
    EXPECT_NE(d.find("16 triangles"), std::string::npos) << d;
}

TEST(Surfaces, ConfigErrorsNameTheKey) {
    const std::string quad = "[[shapes]]\ntype = 'quad'\ncenter = [0, 0, 0]\nu = [1, 0, 0]\nv = [0, 1, 0]\n";
    std::string e = config_error(quad + "colour = 0.3\n");
    EXPECT_NE(e.find("shapes.0.colour"), std::string::npos) << e;
    EXPECT_NE(e.find("test.toml:6"), std::string::npos) << e;
    e = config_error(quad + "transform = { shear = 2 }\n");
    EXPECT_NE(e.find("shapes.0.transform.shear"), std::string::npos) << e;
    e = config_error(quad + "reflectance = 1.5\n");
    EXPECT_NE(e.find("shapes.0.reflectance"), std::string::npos) << e;
    EXPECT_NE(e.find("[0, 1]"), std::string::npos) << e;
    e = config_error(quad + "reflectance = [0.5, -0.1, 0.5]\n");
    EXPECT_NE(e.find("shapes.0.reflectance"), std::string::npos) << e;
    e = config_error(quad + "material = 'black'\nreflectance = 0.5\n");   // black takes no reflectance
    EXPECT_NE(e.find("shapes.0.reflectance"), std::string::npos) << e;
    e = config_error(quad + "material = 'dielectric'\n");   // glass needs a closed shape
    EXPECT_NE(e.find("shapes.0.material"), std::string::npos) << e;
    EXPECT_NE(e.find("closed"), std::string::npos) << e;
    e = config_error("[[shapes]]\ntype = 'sphere'\n");
    EXPECT_NE(e.find("shapes.0.center"), std::string::npos) << e;
    e = config_error("[[shapes]]\ntype = 'sphere'\ncenter = [0, 0, 0]\nradius = 0\n");
    EXPECT_NE(e.find("shapes.0.radius"), std::string::npos) << e;
    e = config_error("[[shapes]]\ntype = 'sphere'\ncenter = [0, 0, 0]\nradius = 1\ntransform = { scale = 2 }\n");
    EXPECT_NE(e.find("shapes.0.transform"), std::string::npos) << e;
    e = config_error("[[shapes]]\ntype = 'cone'\n");
    EXPECT_NE(e.find("sphere"), std::string::npos) << e;   // the allowed types
    e = config_error("[[shapes]]\ncenter = [0, 0, 0]\n");
    EXPECT_NE(e.find("shapes.0.type"), std::string::npos) << e;
    e = config_error("[[shapes]]\ntype = 'quad'\ncenter = [0, 0, 0]\nu = [1, 0, 0]\nv = [2, 0, 0]\n");
    EXPECT_NE(e.find("shapes.0.v"), std::string::npos) << e;
    e = config_error("[[shapes]]\ntype = 'box'\nmin = [0, 0, 0]\nmax = [1, 0, 1]\n");
    EXPECT_NE(e.find("shapes.0.max"), std::string::npos) << e;
    e = config_error("[[shapes]]\ntype = 'box'\nmin = [0, 0, 0]\n");
    EXPECT_NE(e.find("shapes.0.max"), std::string::npos) << e;
    e = config_error("[[shapes]]\ntype = 'mesh'\nfile = 'no_such_mesh.obj'\n");
    EXPECT_NE(e.find("shapes.0.file"), std::string::npos) << e;
    e = config_error(quad + "transform = { scale = [1, 0, 1] }\n");
    EXPECT_NE(e.find("shapes.0.transform.scale"), std::string::npos) << e;
    e = config_error(quad + "transform = { rotate = [0, 0, 0, 10] }\n");
    EXPECT_NE(e.find("shapes.0.transform.rotate"), std::string::npos) << e;
    e = config_error(quad + "transform = { rotate = [0, 0, 10] }\n");
    EXPECT_NE(e.find("shapes.0.transform.rotate"), std::string::npos) << e;
}

TEST(Surfaces, EmbreeDeviceOnlyWhenShapesExist) {
    const size_t before = Surfaces::devices_created();
    std::vector<Params> none;
    auto empty = Surfaces::create(none);
    EXPECT_EQ(Surfaces::devices_created(), before);
    EXPECT_EQ(empty->triangle_count(), 0u);
    SurfaceHit h;
    EXPECT_FALSE(empty->intersect(ray({0, 0, 0}, {0, 0, 1}), kInfinity, h));
    EXPECT_FALSE(empty->occluded(ray({0, 0, 0}, {0, 0, 1}), kInfinity));
    EXPECT_NE(empty->describe().find("no Embree device"), std::string::npos);
    EXPECT_THROW(build("[[shapes]]\ntype = 'box'\nmin = [0, 0, 0]\nmax = [1, 1, 1]\nbogus = 1\n"), ConfigError);
    EXPECT_EQ(Surfaces::devices_created(), before);   // config errors come before any device
    auto s = build("[[shapes]]\ntype = 'box'\nmin = [0, 0, 0]\nmax = [1, 1, 1]\n");
    EXPECT_EQ(Surfaces::devices_created(), before + 1);
}

TEST(Surfaces, ConcurrentQueriesMatchSerialOnes) {
    auto s = build("[[shapes]]\ntype = 'box'\nmin = [-1, -1, -1]\nmax = [1, 1, 1]\n"
                   "[[shapes]]\ntype = 'mesh'\nfile = 'tetra.obj'\ntransform = { translate = [0.5, 0.5, 2] }\n");
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(-3, 3);
    std::vector<Ray> rays;
    for (int i = 0; i < 4000; ++i) rays.push_back(Ray{Vec3(u(rng), u(rng), u(rng)), random_dir(rng)});
    std::vector<double> serial(rays.size()), parallel(rays.size());
    for (size_t i = 0; i < rays.size(); ++i) {
        SurfaceHit h;
        serial[i] = s->intersect(rays[i], kInfinity, h) ? h.t : -1;
    }
    std::vector<std::thread> threads;
    for (int k = 0; k < 4; ++k)
        threads.emplace_back([&, k] {
            for (size_t i = k; i < rays.size(); i += 4) {
                SurfaceHit h;
                parallel[i] = s->intersect(rays[i], kInfinity, h) ? h.t : -1;
            }
        });
    for (auto& t : threads) t.join();
    EXPECT_EQ(serial, parallel);
}

TEST(Surfaces, SphereHitsFromOutsideAndInsideInDouble) {
    const size_t before = Surfaces::devices_created();
    auto s = build("[[shapes]]\ntype = 'sphere'\ncenter = [1, 2, 3]\nradius = 0.5\nmaterial = 'dielectric'\n");
    EXPECT_EQ(Surfaces::devices_created(), before);   // spheres alone build no Embree device
    EXPECT_EQ(s->triangle_count(), 0u);
    EXPECT_TRUE(s->bounds().lo.isApprox(Vec3(0.5, 1.5, 2.5)));
    SurfaceHit h;
    ASSERT_TRUE(s->intersect(ray({1, 2, 10}, {0, 0, -1}), kInfinity, h));
    EXPECT_NEAR(h.t, 6.5, 1e-12);
    EXPECT_TRUE(h.normal.isApprox(Vec3(0, 0, 1), 1e-12));
    EXPECT_FALSE(h.exiting);
    ASSERT_NE(h.specular, nullptr);
    EXPECT_EQ(h.specular->name(), "dielectric");
    EXPECT_TRUE((h.reflectance == 0.0).all());
    ASSERT_TRUE(s->intersect(ray({1, 2, 3}, {1, 0, 0}), kInfinity, h));   // from the centre
    EXPECT_NEAR(h.t, 0.5, 1e-12);
    EXPECT_TRUE(h.normal.isApprox(Vec3(-1, 0, 0), 1e-12));   // faces the ray
    EXPECT_TRUE(h.exiting);
    EXPECT_FALSE(s->intersect(ray({1, 2, 10}, {0, 0, -1}), 6.4, h));
    EXPECT_TRUE(s->occluded(ray({1, 2, 10}, {0, 0, -1}), 6.6));
    EXPECT_FALSE(s->occluded(ray({1, 2, 10}, {0, 0, -1}), 6.4));
    EXPECT_FALSE(s->intersect(ray({1.6, 2, 10}, {0, 0, -1}), kInfinity, h));   // misses
    // Random chords: both ends on the sphere, the second found from just inside the first.
    std::mt19937_64 rng(4);
    for (int i = 0; i < 2000; ++i) {
        const Vec3 o = Vec3(1, 2, 3) + 3.0 * random_dir(rng);
        const Vec3 target = Vec3(1, 2, 3) + 0.45 * random_dir(rng);
        ASSERT_TRUE(s->intersect(ray(o, target - o), kInfinity, h));
        EXPECT_NEAR((h.position - Vec3(1, 2, 3)).norm(), 0.5, 1e-12);
        EXPECT_FALSE(h.exiting);
        const Vec3 d = (target - o).normalized();
        const Ray inside{h.position - 2.0 * h.epsilon * h.normal, d};
        SurfaceHit far;
        ASSERT_TRUE(s->intersect(inside, kInfinity, far));
        EXPECT_TRUE(far.exiting);
        EXPECT_NEAR((far.position - Vec3(1, 2, 3)).norm(), 0.5, 1e-12);
        EXPECT_GT(far.t, 1e-6);
    }
}

TEST(Surfaces, SpheresAndTrianglesTogetherGiveTheClosestHit) {
    auto s = build("[[shapes]]\ntype = 'quad'\ncenter = [0, 0, 1]\nu = [1, 0, 0]\nv = [0, 1, 0]\nmaterial = 'mirror'\n"
                   "[[shapes]]\ntype = 'sphere'\ncenter = [0, 0, 3]\nradius = 0.5\nreflectance = 0.7\n");
    SurfaceHit h;
    ASSERT_TRUE(s->intersect(ray({0, 0, 0}, {0, 0, 1}), kInfinity, h));
    EXPECT_NEAR(h.t, 1.0, 1e-12);
    ASSERT_NE(h.specular, nullptr);
    EXPECT_EQ(h.specular->name(), "mirror");
    ASSERT_TRUE(s->intersect(ray({0, 0, 1.5}, {0, 0, 1}), kInfinity, h));
    EXPECT_NEAR(h.t, 1.0, 1e-12);
    EXPECT_EQ(h.specular, nullptr);
    EXPECT_TRUE(h.reflectance.isApprox(Rgb::Constant(0.7)));
    ASSERT_TRUE(s->intersect(ray({0, 0, 5}, {0, 0, -1}), kInfinity, h));
    EXPECT_NEAR(h.t, 1.5, 1e-12);
    const std::string d = s->describe();
    EXPECT_NE(d.find("1 sphere"), std::string::npos) << d;
    EXPECT_NE(d.find("mirror"), std::string::npos) << d;
}

TEST(Surfaces, DielectricMeshesAreClosedAndTurnedOutwards) {
    const vpm::test::ScratchDir scratch;
    const fs::path& dir = scratch.path;
    // The tetrahedron wound inwards: every face reversed.
    std::ofstream(dir / "inward.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 4 2\nf 1 3 4\nf 2 4 3\n";
    std::ofstream(dir / "open.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 4 2\nf 1 3 4\n";
    std::ofstream(dir / "mixed.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 4 2\nf 1 3 4\nf 2 4 3\n";
    for (const char* file : {"tetra.obj", "inward.obj"}) {
        const fs::path base = std::string(file) == "tetra.obj" ? fs::path(VPM_TEST_DATA_DIR) : dir;
        auto s = build(std::string("[[shapes]]\ntype = 'mesh'\nfile = '") + file + "'\nmaterial = 'dielectric'\n", base);
        SurfaceHit h;
        ASSERT_TRUE(s->intersect(ray({0.2, 0.2, -1}, {0, 0, 1}), kInfinity, h)) << file;
        EXPECT_FALSE(h.exiting) << file;
        ASSERT_TRUE(s->intersect(ray({0.2, 0.2, 0.1}, {0, 0, 1}), kInfinity, h)) << file;
        EXPECT_TRUE(h.exiting) << file;
        ASSERT_TRUE(s->intersect(ray({0.2, 0.2, 0.1}, {0, 0, -1}), kInfinity, h)) << file;
        EXPECT_TRUE(h.exiting) << file;
    }
    auto box = build("[[shapes]]\ntype = 'box'\nmin = [0, 0, 0]\nmax = [1, 1, 1]\nmaterial = 'dielectric'\n"
                     "[shapes.transform]\nscale = [-1, 1, 1]\n");   // a mirroring transform turns the winding
    SurfaceHit h;
    ASSERT_TRUE(box->intersect(ray({-0.5, 0.5, 2}, {0, 0, -1}), kInfinity, h));
    EXPECT_FALSE(h.exiting);
    ASSERT_TRUE(box->intersect(ray({-0.5, 0.5, 0.5}, {0, 0, -1}), kInfinity, h));
    EXPECT_TRUE(h.exiting);
    for (const char* bad : {"open.obj", "mixed.obj"}) {
        std::string e;
        try {
            build(std::string("[[shapes]]\ntype = 'mesh'\nfile = '") + bad + "'\nmaterial = 'dielectric'\n", dir);
        } catch (const ConfigError& err) {
            e = err.what();
        }
        EXPECT_NE(e.find("shapes.0.material"), std::string::npos) << bad << ": " << e;
        EXPECT_NE(e.find("closed"), std::string::npos) << bad << ": " << e;
    }
    // An open mesh is fine for a mirror.
    EXPECT_NO_THROW(build("[[shapes]]\ntype = 'mesh'\nfile = 'open.obj'\nmaterial = 'mirror'\n", dir));
}

// Shapes from 1e-6 to 1e6 in one scene (issue 61): a glass sphere of radius 1e-6, a unit box, a
// mirror quad of half-size 10 and a black sphere of radius 1e6 far below. Each is traced at its
// own scale: chords of the tiny sphere found from just inside it, rays leaving it outward meet
// nothing of it, and rays leaving the box's faces find the analytic box (Embree's float frame is
// centred on the triangles, which the huge sphere does not move).
TEST(Surfaces, EachShapeIsTracedAtItsOwnScale) {
    auto s = build("[[shapes]]\ntype = 'sphere'\ncenter = [0, 0, 0]\nradius = 1e-6\nmaterial = 'dielectric'\n"
                   "[[shapes]]\ntype = 'box'\nmin = [3, 0, 0]\nmax = [4, 1, 1]\n"
                   "[[shapes]]\ntype = 'quad'\ncenter = [0, 0, -50]\nu = [10, 0, 0]\nv = [0, 10, 0]\nmaterial = 'mirror'\n"
                   "[[shapes]]\ntype = 'sphere'\ncenter = [0, -2e6, 0]\nradius = 1e6\nmaterial = 'black'\n");
    const double r = 1e-6;
    std::mt19937_64 rng(61);
    int chords_wrong = 0, outward_self = 0;
    for (int i = 0; i < 2000; ++i) {
        const Vec3 o = 3e-6 * random_dir(rng);
        const Vec3 target = 0.9 * r * random_dir(rng);
        const Vec3 d = (target - o).normalized();
        SurfaceHit h;
        ASSERT_TRUE(s->intersect(Ray{o, d}, kInfinity, h));
        ASSERT_NEAR(h.position.norm(), r, 1e-12 * r);
        ASSERT_GT(h.epsilon, 0.0);
        ASSERT_LT(h.epsilon, 1e-9 * r);
        // The chord's far end, from the origin moved inside by the hit's own offset.
        const double b = h.position.dot(d);
        const double chord = -2.0 * b;   // |p + t d| = r again
        SurfaceHit far;
        if (!s->intersect(Ray{h.position - h.epsilon * h.normal, d}, kInfinity, far) || !far.exiting ||
            std::abs(far.t - chord) > 1e-9 * r)
            ++chords_wrong;
        // Reflected outward: nothing of the tiny sphere is met again.
        const Vec3 refl = d - 2.0 * d.dot(h.normal) * h.normal;
        SurfaceHit out;
        if (s->intersect(Ray{h.position + h.epsilon * h.normal, refl}, kInfinity, out) && out.t < 1.0) ++outward_self;
    }
    EXPECT_EQ(chords_wrong, 0);
    EXPECT_EQ(outward_self, 0);
    // Rays starting on the box's faces: outward ones miss it, inward ones leave where the analytic
    // box says.
    const Bounds3 box{Vec3(3, 0, 0), Vec3(4, 1, 1)};
    std::uniform_real_distribution<double> u(0, 1);
    int self_hits = 0, inward_wrong = 0;
    for (int i = 0; i < 3000; ++i) {
        Vec3 p = box.lo + Vec3(u(rng), u(rng), u(rng));
        const int a = i % 3;
        const bool high = (i / 3) % 2;
        p[a] = high ? box.hi[a] : box.lo[a];
        Vec3 n = Vec3::Zero();
        n[a] = high ? 1.0 : -1.0;
        Vec3 d = random_dir(rng);
        if (d.dot(n) < 0) d = -d;
        SurfaceHit h;
        if (s->intersect(Ray{p, d}, kInfinity, h) && h.t < 10.0) ++self_hits;
        double t0, t1;
        ASSERT_TRUE(box.intersect(Ray{p, -d}, kInfinity, t0, t1));
        if (t1 > 1e-3 && (!s->intersect(Ray{p, -d}, kInfinity, h) || std::abs(h.t - t1) > 1e-9)) ++inward_wrong;
    }
    EXPECT_EQ(self_hits, 0);
    EXPECT_LE(inward_wrong, 2);   // a ray grazing an edge may slip through it
}

TEST(Surfaces, EachClosedPartOfADielectricMeshFacesOutOfTheGlass) {
    // Two tetrahedra apart, the second wound inwards (its volume alone negative; the sum positive):
    // both must read as solids. And a shell: a tetrahedron inside a larger one, both wound
    // outwards in the file; the inner part is the cavity and must face into it.
    const vpm::test::ScratchDir scratch;
    const fs::path& dir = scratch.path;
    const char* outward = "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";   // tetra.obj's winding, checked above
    const char* inward = "f 1 2 3\nf 1 4 2\nf 1 3 4\nf 2 4 3\n";
    {
        std::ofstream f(dir / "two.obj");
        f << "v 0 0 0\nv 2 0 0\nv 0 2 0\nv 0 0 2\n" << outward;
        f << "v 5 0 0\nv 6 0 0\nv 5 1 0\nv 5 0 1\n";
        for (const char* c = inward; *c; ++c) f << (std::isdigit(*c) ? char(*c + 4) : *c);
    }
    {
        std::ofstream f(dir / "shell.obj");
        f << "v -1 -1 -1\nv 5 -1 -1\nv -1 5 -1\nv -1 -1 5\n" << outward;
        f << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n";
        for (const char* c = outward; *c; ++c) f << (std::isdigit(*c) ? char(*c + 4) : *c);
    }
    SurfaceHit h;
    auto two = build("[[shapes]]\ntype = 'mesh'\nfile = 'two.obj'\nmaterial = 'dielectric'\n", dir);
    ASSERT_TRUE(two->intersect(ray({5.2, 0.2, -1}, {0, 0, 1}), kInfinity, h));
    EXPECT_FALSE(h.exiting);   // entering the second solid
    ASSERT_TRUE(two->intersect(ray({5.2, 0.2, 0.1}, {0, 0, 1}), kInfinity, h));
    EXPECT_TRUE(h.exiting);
    ASSERT_TRUE(two->intersect(ray({0.2, 0.2, -1}, {0, 0, 1}), kInfinity, h));
    EXPECT_FALSE(h.exiting);   // the first is untouched
    auto shell = build("[[shapes]]\ntype = 'mesh'\nfile = 'shell.obj'\nmaterial = 'dielectric'\n", dir);
    ASSERT_TRUE(shell->intersect(ray({0.2, 0.2, -0.5}, {0, 0, 1}), kInfinity, h));   // glass into the cavity
    EXPECT_TRUE(h.exiting);
    ASSERT_TRUE(shell->intersect(ray({0.2, 0.2, 0.1}, {0, 0, 1}), kInfinity, h));    // the cavity into glass
    EXPECT_FALSE(h.exiting);
    ASSERT_TRUE(shell->intersect(ray({0.2, 0.2, -2}, {0, 0, 1}), kInfinity, h));     // air into glass
    EXPECT_FALSE(h.exiting);
}

TEST(Surfaces, GlassRestingFlatOnAnotherShapeIsReported) {
    // A glass box standing on a floor quad shares its bottom face's plane with the floor: reported
    // (the scene warns). Lifted by 1e-4, a Lambertian box on the floor, or a glass sphere: not.
    const std::string floor = "[[shapes]]\ntype = \"quad\"\ncenter = [0, 0, 0]\nu = [2, 0, 0]\nv = [0, 0, -2]\n";
    const auto box = [](double y0, const char* material) {
        return "[[shapes]]\ntype = \"box\"\nmin = [-0.3, " + std::to_string(y0) + ", -0.3]\nmax = [0.3, 0.5, 0.3]\nmaterial = \"" +
               material + "\"\n";
    };
    const auto touching = build(floor + box(0.0, "dielectric"))->coplanar_glass_contacts();
    ASSERT_EQ(touching.size(), 1u);
    EXPECT_EQ(touching[0].first, 1u);
    EXPECT_EQ(touching[0].second, 0u);
    EXPECT_TRUE(build(floor + box(1e-4, "dielectric"))->coplanar_glass_contacts().empty());
    EXPECT_TRUE(build(floor + box(0.0, "lambertian"))->coplanar_glass_contacts().empty());
    EXPECT_TRUE(build(floor + "[[shapes]]\ntype = \"sphere\"\ncenter = [0, 0.3, 0]\nradius = 0.3\nmaterial = \"dielectric\"\n")
                    ->coplanar_glass_contacts()
                    .empty());
    // A glass box beside the floor's edge, its face in the floor's plane but off the quad: not touching.
    const std::string away = "[[shapes]]\ntype = \"box\"\nmin = [2.5, 0, 0]\nmax = [3, 0.5, 0.5]\nmaterial = \"dielectric\"\n";
    EXPECT_TRUE(build(floor + away)->coplanar_glass_contacts().empty());
    // A million units from the origin: touching is reported, a 1e-3 gap is not (rounding is judged at
    // the triangles' size, as Embree sees them about the scene's centre).
    const auto far = [](double y0) {
        return std::string("[[shapes]]\ntype = \"quad\"\ncenter = [1e6, 0, 1e6]\nu = [2, 0, 0]\nv = [0, 0, -2]\n") +
               "[[shapes]]\ntype = \"box\"\nmin = [999999.7, " + std::to_string(y0) +
               ", 999999.7]\nmax = [1000000.3, 0.5, 1000000.3]\nmaterial = \"dielectric\"\n";
    };
    EXPECT_EQ(build(far(0.0))->coplanar_glass_contacts().size(), 1u);
    EXPECT_TRUE(build(far(1e-3))->coplanar_glass_contacts().empty());
}
