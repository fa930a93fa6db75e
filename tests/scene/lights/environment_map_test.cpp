// The environment map light (type = "environment", file = lat-long EXR): its sampling pdf
// integrates to 1 and matches a histogram of its samples (chi-square, with a check that a wrong pdf
// fails), sample weights agree with the lookup, the lat-long convention and rotate_y put a bright
// texel where README says, the photon power averages to power(), and bad inputs are clear errors.
#include <gtest/gtest.h>

#include <functional>
#include <iostream>
#include <limits>

#include "core/error.h"
#include "render/run/image_io.h"
#include "scene/lights/emission_bounds.h"
#include "scene/lights/latlong_map.h"
#include "scene/lights/light_registry.h"

#include "support/chi_square.h"
#include "support/io_test_util.h"
#include "support/sample_statistics.h"

using namespace vpm;

namespace {

class EnvironmentMap : public vpm_test::TempDirTest {
protected:
    // Writes `image` as dir_/name and returns the light of `[[lights]] type = "environment"` + extra,
    // read from a config in dir_ (so relative paths resolve there).
    std::unique_ptr<Light> light(const std::string& extra) {
        auto doc = parse_config("[[lights]]\ntype = 'environment'\n" + extra, (dir_ / "env.toml").string(), dir_);
        toml::table resolved;
        Params root(doc, &resolved);
        auto tables = root.tables("lights");
        return make_light(tables.at(0));
    }
    void write(const std::string& name, const Image& image) { write_exr(dir_ / name, image); }
};

// 32 x 16: a sky gradient, a black block, a bright 2 x 1 "sun" and a coloured patch.
Image test_map() {
    Image im(32, 16);
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 32; ++x) {
            Rgb c = Rgb(0.2, 0.3, 0.6) * (1.0 + 0.1 * x) * (y < 8 ? 1.0 : 0.3);
            if (x >= 20 && x < 26 && y >= 10 && y < 14) c = Rgb::Zero();
            if ((x == 5 || x == 6) && y == 3) c = Rgb(60, 50, 40);
            if (x == 13 && y == 0) c = Rgb(3, 0, 0);   // only red: non-zero luminance all the same
            im.set(x, y, c);
        }
    return im;
}

// World direction's azimuth phi in [0, 2 pi) and z = cos theta (latlong_map.h's convention).
void phi_z(const Vec3& d, double& phi, double& z) {
    double u, v;
    latlong_coordinates(d, u, v);
    phi = 2.0 * kPi * u;
    z = d.y();
}

double overlap(double a0, double a1, double b0, double b1) { return std::max(0.0, std::min(a1, b1) - std::max(a0, b0)); }

}  // namespace

TEST_F(EnvironmentMap, PdfIntegratesToOneOverTheSphere) {
    write("map.exr", test_map());
    auto l = light("file = 'map.exr'\nrotate_y = 30\n");
    // Monte Carlo integral of the solid-angle pdf over uniform directions: 4 pi E[pdf] = 1.
    Rng rng(5, 1);
    test::Sample s;
    for (int i = 0; i < 2000000; ++i) {
        const double u1 = rng.uniform(), u2 = rng.uniform();
        const Vec3 w(std::sqrt(1 - (1 - 2 * u1) * (1 - 2 * u1)) * std::cos(2 * kPi * u2), 1 - 2 * u1,
                     std::sqrt(1 - (1 - 2 * u1) * (1 - 2 * u1)) * std::sin(2 * kPi * u2));
        s.add(4.0 * kPi * l->pdf_incident(Vec3::Zero(), w));
    }
    std::cout << "integral of the pdf over the sphere: " << s.mean() << " +- " << s.se() << "\n";
    EXPECT_NEAR(s.mean(), 1.0, 4.0 * s.se());
    EXPECT_LT(s.se(), 0.01);
    // Exact: the texel pdfs times their solid angles (one direction per texel, unrotated map).
    auto u = light("file = 'map.exr'\n");
    double sum = 0.0;
    for (int j = 0; j < 16; ++j)
        for (int i = 0; i < 32; ++i) {
            const double omega = 2 * kPi / 32 * (std::cos(kPi * j / 16) - std::cos(kPi * (j + 1) / 16));
            sum += omega * u->pdf_incident(Vec3::Zero(), latlong_direction((i + 0.5) / 32, (j + 0.5) / 16));
        }
    EXPECT_NEAR(sum, 1.0, 1e-12);
}

TEST_F(EnvironmentMap, SampledDirectionsMatchThePdfChiSquare) {
    write("map.exr", test_map());
    auto l = light("file = 'map.exr'\n");
    // Histogram over a theta x phi grid not aligned with the texels (24 x 48 against 16 x 32).
    const int nt = 24, np = 48, n = 1000000;
    std::vector<double> observed(nt * np, 0.0);
    Rng rng(99, 4);
    LightSample s;
    for (int k = 0; k < n; ++k) {
        ASSERT_TRUE(l->sample_incident(Vec3::Zero(), rng, s));
        double phi, z;
        phi_z(s.wi, phi, z);
        const int bt = std::min(nt - 1, int(std::acos(std::max(-1.0, std::min(1.0, z))) / kPi * nt));
        const int bp = std::min(np - 1, int(phi / (2 * kPi) * np));
        observed[bt * np + bp] += 1.0;
    }
    // Expected counts: the piecewise-constant pdf integrated exactly over each bin, the overlap of a
    // texel and a bin being (azimuth overlap) x (cos theta overlap). `texel_pdf` gives a pdf per texel.
    auto expected_for = [&](const std::function<double(int, int)>& texel_pdf) {
        std::vector<double> e(nt * np, 0.0);
        for (int bt = 0; bt < nt; ++bt)
            for (int bp = 0; bp < np; ++bp) {
                const double bz1 = std::cos(kPi * bt / nt), bz0 = std::cos(kPi * (bt + 1) / nt);
                const double bp0 = 2 * kPi * bp / np, bp1 = 2 * kPi * (bp + 1) / np;
                double p = 0.0;
                for (int j = 0; j < 16; ++j) {
                    const double tz1 = std::cos(kPi * j / 16), tz0 = std::cos(kPi * (j + 1) / 16);
                    const double oz = overlap(bz0, bz1, tz0, tz1);
                    if (oz == 0.0) continue;
                    for (int i = 0; i < 32; ++i) {
                        const double op = overlap(bp0, bp1, 2 * kPi * i / 32, 2 * kPi * (i + 1) / 32);
                        if (op > 0.0) p += texel_pdf(i, j) * oz * op;
                    }
                }
                e[bt * np + bp] = n * p;
            }
        return e;
    };
    auto light_pdf = [&](int i, int j) {
        return l->pdf_incident(Vec3::Zero(), latlong_direction((i + 0.5) / 32, (j + 0.5) / 16));
    };
    const test::ChiSquare good = test::chi_square(observed, expected_for(light_pdf));
    std::cout << "chi-square of " << n << " sampled directions in " << nt << " x " << np << " bins: " << good.statistic
              << " with " << good.dof << " dof (" << good.pooled_cells << " cells pooled), p = " << good.p << "\n";
    EXPECT_GT(good.p, 1e-3);
    // Power of the test: the pdf one gets by forgetting the rows' sin(theta) weighting (texels chosen
    // by luminance alone, then uniformly in solid angle) must be rejected by the same samples.
    const Image map = test_map();
    double lum_sum = 0.0;
    for (int j = 0; j < 16; ++j)
        for (int i = 0; i < 32; ++i) lum_sum += luminance(map.at(i, j));
    auto wrong_pdf = [&](int i, int j) {
        const double omega = 2 * kPi / 32 * (std::cos(kPi * j / 16) - std::cos(kPi * (j + 1) / 16));
        return luminance(map.at(i, j)) / lum_sum / omega;
    };
    const test::ChiSquare bad = test::chi_square(observed, expected_for(wrong_pdf));
    std::cout << "against the pdf without sin(theta): " << bad.statistic << " with " << bad.dof << " dof, p = " << bad.p
              << "\n";
    EXPECT_LT(bad.p, 1e-3);
}

TEST_F(EnvironmentMap, SampleWeightAndPdfAgreeWithTheLookup) {
    write("map.exr", test_map());
    auto l = light("file = 'map.exr'\nrotate_y = -47.5\nscale = [2, 1, 0.5]\n");
    Rng rng(3, 3);
    LightSample s;
    for (int k = 0; k < 100000; ++k) {
        ASSERT_TRUE(l->sample_incident(Vec3(1, 2, 3), rng, s));
        ASSERT_NEAR(s.wi.norm(), 1.0, 1e-12);
        ASSERT_EQ(s.distance, kInfinity);
        ASSERT_GT(s.pdf, 0.0);
        ASSERT_NEAR(l->pdf_incident(Vec3::Zero(), s.wi), s.pdf, 1e-12 * s.pdf) << k;
        const Rgb expect = l->escaped_radiance(s.wi) / s.pdf;
        for (int c = 0; c < 3; ++c) ASSERT_NEAR(s.weight[c], expect[c], 1e-12 * expect.maxCoeff()) << k;
    }
    // Black texels: radiance 0 and pdf 0 there.
    const Vec3 in_black = [] {   // texel (22, 12) of the unrotated map, turned by -47.5 degrees
        const Vec3 d = latlong_direction(22.5 / 32, 12.5 / 16);
        const double a = -47.5 * kPi / 180;
        return Vec3(std::cos(a) * d.x() + std::sin(a) * d.z(), d.y(), -std::sin(a) * d.x() + std::cos(a) * d.z());
    }();
    EXPECT_EQ(l->pdf_incident(Vec3::Zero(), in_black), 0.0);
    EXPECT_EQ(l->escaped_radiance(in_black).maxCoeff(), 0.0);
}

TEST_F(EnvironmentMap, ConventionAndRotationPutABrightTexelWhereDocumented) {
    // 16 x 8, black but texel (8, 3): u in [0.5, 0.5625], v in [0.375, 0.5], i.e. azimuth 0 .. 22.5
    // degrees from -Z towards +X, elevation 0 .. 22.5 degrees. Its centre is at azimuth and
    // elevation 11.25 degrees: (sin az cos el, sin el, -cos az cos el).
    Image im(16, 8);
    im.set(8, 3, Rgb(5, 6, 7));
    write("dot.exr", im);
    const double a = 11.25 * kPi / 180;
    const Vec3 centre(std::sin(a) * std::cos(a), std::sin(a), -std::cos(a) * std::cos(a));
    // rotate_y = 90 (right-handed about +Y) takes (x, y, z) to (z, y, -x): -Z goes to -X.
    const Vec3 turned(centre.z(), centre.y(), -centre.x());
    auto plain = light("file = 'dot.exr'\n");
    auto rotated = light("file = 'dot.exr'\nrotate_y = 90\n");
    EXPECT_EQ(plain->escaped_radiance(centre)[2], 7.0);
    EXPECT_EQ(plain->escaped_radiance(turned)[2], 0.0);
    EXPECT_EQ(rotated->escaped_radiance(turned)[2], 7.0);
    EXPECT_EQ(rotated->escaped_radiance(centre)[2], 0.0);
    EXPECT_EQ(plain->escaped_radiance(Vec3(0, 0.05, -1).normalized())[1], 6.0);   // -Z, just above the horizon
    EXPECT_EQ(plain->escaped_radiance(Vec3(0, 0.1, 1).normalized())[1], 0.0);   // behind: +Z
    // Every sample comes from the bright texel: within its angular extent of the centre.
    Rng rng(8, 8);
    LightSample s;
    for (int k = 0; k < 10000; ++k) {
        ASSERT_TRUE(rotated->sample_incident(Vec3::Zero(), rng, s));
        ASSERT_GT(s.wi.dot(turned), std::cos(16.5 * kPi / 180)) << s.wi.transpose();
        ASSERT_EQ(rotated->escaped_radiance(s.wi)[0], 5.0);
    }
    // The top row is the zenith.
    Image top(8, 4);
    for (int x = 0; x < 8; ++x) top.set(x, 0, Rgb(1, 1, 1));
    write("top.exr", top);
    EXPECT_EQ(light("file = 'top.exr'\n")->escaped_radiance(Vec3::UnitY())[0], 1.0);
    EXPECT_EQ(light("file = 'top.exr'\n")->escaped_radiance(-Vec3::UnitY())[0], 0.0);
}

TEST_F(EnvironmentMap, ConstantMapHasTheConstantSkysPowerAndPdf) {
    Image im(24, 12);
    for (int y = 0; y < 12; ++y)
        for (int x = 0; x < 24; ++x) im.set(x, y, Rgb(0.25, 0.5, 1.0));
    write("const.exr", im);
    auto map = light("file = 'const.exr'\nrotate_y = 17\nscale = 2\n");
    auto sky = light("radiance = [0.5, 1.0, 2.0]\n");
    const Bounds3 b{Vec3(-1, -2, -1), Vec3(3, 1, 2)};
    map->set_scene_bounds(b);
    sky->set_scene_bounds(b);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(map->power()[c], sky->power()[c], 1e-12 * sky->power()[c]);
    Rng rng(1, 2);
    LightSample s;
    for (int k = 0; k < 1000; ++k) {
        ASSERT_TRUE(map->sample_incident(Vec3::Zero(), rng, s));
        ASSERT_NEAR(s.pdf, 1.0 / (4 * kPi), 1e-12);
        ASSERT_NEAR(s.weight[1], 4 * kPi, 1e-9);
    }
}

TEST_F(EnvironmentMap, PhotonPowerAveragesToPowerAndPowerIsTheIntegralOfRadianceTimesProjectedArea) {
    write("map.exr", test_map());
    auto l = light("file = 'map.exr'\nrotate_y = 30\n");
    const Bounds3 b{Vec3(-1, -2, -1), Vec3(3, 1, 2)};   // faces 9, 12, 12
    l->set_scene_bounds(b);
    EmissionBounds eb;
    eb.set(b);
    const double power = l->power()[0];
    ASSERT_GT(power, 0.0);
    // power() against brute force: 4 pi E[L(w) A_proj(w)] over uniform directions.
    Rng rng(11, 0);
    test::Sample brute, photons;
    for (int i = 0; i < 1000000; ++i) {
        const double z = 1 - 2 * rng.uniform(), phi = 2 * kPi * rng.uniform(), r = std::sqrt(1 - z * z);
        const Vec3 w(r * std::cos(phi), z, r * std::sin(phi));
        brute.add(4 * kPi * l->escaped_radiance(w)[0] * eb.projected_area(w));
    }
    for (int i = 0; i < 400000; ++i) {
        const EmissionSample e = l->sample_emission(rng);
        ASSERT_FALSE(b.contains(e.ray.origin));
        double t0, t1;
        ASSERT_TRUE(b.intersect(e.ray, kInfinity, t0, t1)) << "a photon that misses what can be lit";
        photons.add(e.power[0]);
    }
    std::cout << "power " << power << ", brute force " << brute.mean() << " +- " << brute.se() << ", photon mean "
              << photons.mean() << " +- " << photons.se() << "\n";
    EXPECT_NEAR(brute.mean(), power, 4.0 * brute.se());
    EXPECT_NEAR(photons.mean(), power, 4.0 * photons.se());
    EXPECT_LT(photons.se(), 0.01 * power);
}

TEST_F(EnvironmentMap, AllBlackMapHasZeroPowerAndSaysSo) {
    write("black.exr", Image(8, 4));
    auto l = light("file = 'black.exr'\n");
    l->set_scene_bounds(Bounds3{Vec3(-1, -1, -1), Vec3(1, 1, 1)});
    EXPECT_EQ(l->power().maxCoeff(), 0.0);
    Rng rng(1, 1);
    LightSample s;
    EXPECT_FALSE(l->sample_incident(Vec3::Zero(), rng, s));
    EXPECT_EQ(l->pdf_incident(Vec3::Zero(), Vec3::UnitY()), 0.0);
    EXPECT_EQ(l->sample_emission(rng).power.maxCoeff(), 0.0);
    EXPECT_NE(l->describe().find("zero power"), std::string::npos) << l->describe();
}

TEST_F(EnvironmentMap, BadInputsAreOneClearError) {
    auto message = [&](const std::string& extra) -> std::string {
        try {
            light(extra);
        } catch (const ConfigError& e) {
            return e.what();
        }
        return "no error";
    };
    auto expect_has = [](const std::string& text, const std::string& part) {
        EXPECT_NE(text.find(part), std::string::npos) << "'" << part << "' not in: " << text;
    };
    // Missing file: key and resolved path.
    std::string m = message("file = 'nowhere.exr'\n");
    expect_has(m, "lights.0.file");
    expect_has(m, "nowhere.exr");
    // Not an EXR.
    { std::ofstream(dir_ / "text.exr") << "not an image\n"; }
    m = message("file = 'text.exr'\n");
    expect_has(m, "lights.0.file");
    expect_has(m, "not an OpenEXR file");
    // An empty (zero-byte) file.
    { std::ofstream(dir_ / "empty.exr"); }
    m = message("file = 'empty.exr'\n");
    expect_has(m, "lights.0.file");
    expect_has(m, "empty.exr");
    expect_has(m, "not an OpenEXR file");
    // Negative, NaN and infinite pixels: the file, the pixel and the rule.
    for (float bad : {-0.5f, std::nanf(""), std::numeric_limits<float>::infinity()}) {
        Image im(4, 2);
        im.rgb[3 * (1 * 4 + 2) + 1] = bad;   // pixel (2, 1), green
        write("bad.exr", im);
        m = message("file = 'bad.exr'\n");
        expect_has(m, "lights.0.file");
        expect_has(m, "bad.exr: pixel (2, 1) channel G");
        expect_has(m, "finite and >= 0");
    }
    // Both keys; map keys without a map; a negative scale.
    write("ok.exr", Image(4, 2));
    m = message("file = 'ok.exr'\nradiance = 1\n");
    expect_has(m, "lights.0.radiance");
    expect_has(m, "not both");
    expect_has(message("radiance = 1\nscale = 2\n"), "lights.0.scale: applies to an environment map only");
    expect_has(message("radiance = 1\nrotate_y = 2\n"), "lights.0.rotate_y: applies to an environment map only");
    expect_has(message("file = 'ok.exr'\nscale = -1\n"), "lights.0.scale");
    EXPECT_EQ(message("file = 'ok.exr'\nscale = [1, 2, 3]\nrotate_y = 45\n"), "no error");
    // Issue 24: a turn of 1e300 degrees has no meaningful remainder; one turn either way is allowed.
    for (const char* bad : {"1e300", "361", "-400"}) expect_has(message(std::string("file = 'ok.exr'\nrotate_y = ") + bad + "\n"), "lights.0.rotate_y");
    EXPECT_EQ(message("file = 'ok.exr'\nrotate_y = -360\n"), "no error");
}
