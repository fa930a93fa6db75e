// Issue 21: the path tracer and the photon map against Chandrasekhar's closed form for a
// semi-infinite isotropic medium under a directional light (configs/semi_infinite.toml,
// lib/analysis/study/chandrasekhar_h.h): L = a / (4 pi) E mu0 / (mu + mu0) H(mu) H(mu0), mu0 = 1 here and
// mu = 1 or 0.5 (camera straight above the middle of the top face, or 60 degrees off the normal).
// The expected image mean is the closed form averaged over the camera's rays (mu varies across the
// 2-degree field of view). Tolerances are 3.5 standard errors of the image means.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <string>

#include "analysis/study/chandrasekhar_h.h"
#include "photon/map/photon_map.h"
#include "photon/trace/photon_tracer.h"
#include "render/path/path_tracer.h"
#include "render/photon_map/photon_map_integrator.h"
#include "render/run/run_config.h"
#include "support/render_statistics.h"

using namespace vpm;

namespace {

std::string num(double v) {
    char b[64];
    std::snprintf(b, sizeof b, "%.9g", v);
    return b;
}

// The box: sizes in mean free paths (sigma_t = 1), chosen per albedo from the diffusion length
// 1 / sqrt(3 (1 - a)) (0.8 / 1.8 / 5.8 mean free paths at a = 0.5 / 0.9 / 0.99).
struct Box {
    double half_width, depth;
};

RunConfig semi_infinite(double albedo, double mu, Box box, std::vector<std::string> extra = {}) {
    const double s = std::sqrt(1.0 - mu * mu);
    std::vector<std::string> set = {
        "media.0.albedo=" + num(albedo),
        "media.0.min=[" + num(-box.half_width) + ", " + num(-box.depth) + ", " + num(-box.half_width) + "]",
        "media.0.max=[" + num(box.half_width) + ", 0, " + num(box.half_width) + "]",
        "camera.position=[0, " + num(20.0 * mu) + ", " + num(20.0 * s) + "]"};
    set.insert(set.end(), extra.begin(), extra.end());
    return RunConfig::load(VPM_SOURCE_DIR "/configs/semi_infinite.toml", set);
}

// The closed form averaged over a 32 x 32 grid of image positions (mu = the ray's cosine with +y).
double expected_mean(const RunConfig& config, const ChandrasekharH& h) {
    const Camera& camera = config.scene->camera;
    const int n = 32;
    double sum = 0.0;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const Ray r = camera.generate_ray((i + 0.5) / n * config.render.width, (j + 0.5) / n * config.render.height);
            sum += h.reflected(-r.dir.normalized().y(), 1.0);
        }
    return sum / (n * n);
}

}  // namespace

namespace {

struct Measured {
    test::Sample image;   // image means of independent runs
    double expected = 0.0;
    double z() const { return (image.mean() - expected) / image.se(); }
};

Measured path_traced(double albedo, double mu, Box box, int repeats, int spp) {
    const RunConfig config = semi_infinite(albedo, mu, box);
    Measured m;
    m.expected = expected_mean(config, ChandrasekharH(albedo));
    const WalkSettings walk;   // unbiased: no depth cap
    for (int r = 0; r < repeats; ++r)
        m.image.add(test::image_mean(config, PathTracer(*config.scene, walk), 40 + uint64_t(r), spp));
    std::printf("path tracer, albedo %.2f, mu %.1f: %.6f +- %.6f, closed form %.6f (%+.2f%%, z %.2f)\n", albedo, mu,
                m.image.mean(), m.image.se(), m.expected, 100.0 * (m.image.mean() / m.expected - 1.0), m.z());
    return m;
}

// Independent photon maps (seeds 700 + r), each rendered from both views (mu = 1 and 0.5); the
// camera is 10x farther away than the config's, so the image covers 7 x 7 mean free paths of the
// top face and averages many walks.
std::array<Measured, 2> photon_mapped(double albedo, Box box, int repeats, int photons, int spp,
                                      std::vector<std::string> extra = {}) {
    extra.push_back("photons.count=" + std::to_string(photons));
    extra.push_back("render.integrator=photon_map");
    std::array<Measured, 2> m;
    const std::array<double, 2> mus = {1.0, 0.5};
    std::vector<RunConfig> configs;
    for (int v = 0; v < 2; ++v) {
        std::vector<std::string> set = extra;
        set.push_back("camera.position=[0, " + num(200.0 * mus[v]) + ", " + num(200.0 * std::sqrt(1.0 - mus[v] * mus[v])) + "]");
        configs.push_back(semi_infinite(albedo, mus[v], box, set));
        m[size_t(v)].expected = expected_mean(configs.back(), ChandrasekharH(albedo));
    }
    const PhotonMapSettings& ps = photon_map_settings(configs[0]);
    for (int r = 0; r < repeats; ++r) {
        PhotonTraceSettings ts;
        ts.count = uint64_t(ps.count);
        ts.seed = 700 + uint64_t(r);
        ts.progress = false;
        ts.store_direct = ps.direct == DirectLighting::photon_map;   // as run_photon_pass sets it
        ts.store_probability = ps.store_probability;
        const PhotonMap map(trace_photons(*configs[0].scene, ts).photons);
        for (int v = 0; v < 2; ++v)
            m[size_t(v)].image.add(test::image_mean(configs[size_t(v)], PhotonMapIntegrator(*configs[size_t(v)].scene, ps, map), 60 + uint64_t(r), spp));
    }
    for (int v = 0; v < 2; ++v)
        std::printf("photon map, albedo %.2f, mu %.1f: %.6f +- %.6f, closed form %.6f (%+.2f%%, z %.2f)\n", albedo, mus[size_t(v)],
                    m[size_t(v)].image.mean(), m[size_t(v)].image.se(), m[size_t(v)].expected,
                    100.0 * (m[size_t(v)].image.mean() / m[size_t(v)].expected - 1.0), m[size_t(v)].z());
    return m;
}

}  // namespace

// Box sizes (half width x depth, mean free paths). Checked with the path tracer at twice each size:
// see the figures in each test. The photon-map boxes are wider since their camera sees 7 x 7 mfp.
constexpr Box kBox05{10, 10}, kBox09{20, 20}, kBox099{40, 80};

TEST(SemiInfinite, PathTracerAlbedo05) {
    for (double mu : {1.0, 0.5}) EXPECT_LT(std::abs(path_traced(0.5, mu, kBox05, 8, 1024).z()), 3.5);
}
TEST(SemiInfinite, PathTracerAlbedo09) {
    for (double mu : {1.0, 0.5}) EXPECT_LT(std::abs(path_traced(0.9, mu, kBox09, 8, 1024).z()), 3.5);
}
TEST(SemiInfinite, PathTracerAlbedo099) {
    for (double mu : {1.0, 0.5}) EXPECT_LT(std::abs(path_traced(0.99, mu, kBox099, 8, 2048).z()), 3.5);
}

TEST(SemiInfinite, PhotonMapAlbedo05) {
    for (const Measured& m : photon_mapped(0.5, kBox05, 4, 200000, 16)) EXPECT_LT(std::abs(m.z()), 3.5);
}
TEST(SemiInfinite, PhotonMapAlbedo09) {
    for (const Measured& m : photon_mapped(0.9, kBox09, 4, 400000, 16)) EXPECT_LT(std::abs(m.z()), 3.5);
}
// Albedo 0.99 with the estimators of issue 21 (docs/dense_bias.md): a 60 x 60 x 60 box (the camera
// sees the middle 7 x 7; 26 mean free paths = 4.5 diffusion lengths from every side face). Six maps
// of 1e5 photons rather than three of 2e5: a standard error from three heavy-tailed image means is
// itself unreliable (eight maps of 2e5 measured 0.0010-0.0020; three gave 0.0004-0.0028).
TEST(SemiInfinite, PhotonMapAlbedo099) {
    for (const Measured& m : photon_mapped(0.99, Box{30, 60}, 6, 100000, 16, {"photons.extinction=linear", "photons.clustering=leave_group_out"}))
        EXPECT_LT(std::abs(m.z()), 3.5);
}
