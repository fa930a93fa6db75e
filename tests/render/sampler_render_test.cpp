// render.sampler and photons.sampler (core/sampling/sampler.h) in the renderer:
// - every estimator in the volume furnace, with each sampler on both sides, at its Poisson
//   expectation within 3 standard errors over independent maps (plus the 5% model tolerance on
//   the bias that photon_map_render_test.cpp states for walk-clustered photons);
// - the path tracer in the furnace with each camera sampler, within 3 standard errors;
// - "independent" is the image made without the key; the others make other images;
// - the same image on 1 and 2 threads with "sobol" and "stratified" on both sides;
// - bad values: one clear error naming the key and the allowed values.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>
#include <vector>

#include "core/sampling/sampler.h"
#include "core/sampling/sampler_registry.h"
#include "photon/map/photon_map.h"
#include "photon/trace/photon_tracer.h"
#include "render/path/path_tracer.h"
#include "render/photon_map/photon_map_integrator.h"
#include "render/run/render_loop.h"
#include "render/run/run.h"
#include "render/run/run_config.h"
#include "../support/render_statistics.h"

using namespace vpm;

namespace {

const SamplerKind kKinds[] = {SamplerKind::independent, SamplerKind::stratified, SamplerKind::sobol};

double image_mean(const RunConfig& config, const Integrator& integrator, uint64_t seed, int spp, SamplerKind sampler) {
    RenderOptions o;
    o.width = config.render.width;
    o.height = config.render.height;
    o.spp = spp;
    o.seed = seed;
    o.progress = false;
    o.sampler = sampler;
    RenderStats stats;
    const Image image = render_image(config.scene->camera, integrator, o, stats);
    EXPECT_EQ(stats.nonfinite_samples, 0u);
    double m = 0;
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x) m += image.at(x, y)[1];
    return m / double(image.width * image.height);
}

Image run_image(const std::vector<std::string>& sets) {
    RunOptions o;
    o.progress = false;
    return run(RunConfig::load(VPM_SOURCE_DIR "/configs/uniform_furnace.toml", sets), o).image;
}

}  // namespace

TEST(SamplerRender, EveryEstimatorAtItsExpectationInTheFurnaceWithEverySampler) {
    const RunConfig config = RunConfig::load(VPM_SOURCE_DIR "/configs/uniform_furnace.toml",
                                             {"render.width=16", "render.height=16", "photons.count=40000"});
    PhotonMapSettings ps = photon_map_settings(config);
    const double env = config.scene->escaped_radiance(Vec3::UnitZ())[1];
    const size_t k = 8;
    ps.k = int(k);
    const std::vector<Estimator>& estimators = Estimator::all();
    for (SamplerKind kind : kKinds) {
        std::vector<test::Sample> s(estimators.size());
        for (int r = 0; r < 16; ++r) {
            PhotonTraceSettings ts;
            ts.count = uint64_t(ps.count);
            ts.seed = 5300 + uint64_t(r);
            ts.progress = false;
            ts.sampler = kind;
            const PhotonMap map(trace_photons(*config.scene, ts).photons);
            for (size_t e = 0; e < estimators.size(); ++e) {
                ps.estimator = estimators[e];
                s[e].add(image_mean(config, PhotonMapIntegrator(*config.scene, ps, map), 91 + uint64_t(r), 2, kind) / env);
            }
        }
        for (size_t e = 0; e < estimators.size(); ++e) {
            const double bias = estimators[e].uniform_theory(k, 0, 1.0, 3).error;
            std::printf("%s, %s: mean/truth %.4f +- %.4f (Poisson theory %.4f)\n", sampler_name(kind),
                        estimators[e].name(), s[e].mean(), s[e].se(), 1.0 + bias);
            EXPECT_NEAR(s[e].mean(), 1.0 + bias, 3.0 * s[e].se() + 0.05 * std::abs(bias))
                << sampler_name(kind) << " " << estimators[e].name();
        }
    }
}

TEST(SamplerRender, PathTracerInTheFurnaceWithEveryCameraSampler) {
    const RunConfig config = RunConfig::load(VPM_SOURCE_DIR "/configs/uniform_furnace.toml", {});
    const double env = config.scene->escaped_radiance(Vec3::UnitZ())[1];
    const PathTracer pt(*config.scene);
    for (SamplerKind kind : kKinds) {
        test::Sample means;   // one per sample set: the sets are independent, their points are not
        for (int set = 0; set < 1500; ++set) {
            PathSampler sampler(kind, sampler_key(5, uint64_t(set), 0, 1), 16);
            Rng rng(5, uint64_t(set));
            if (kind != SamplerKind::independent) rng.draw_from(&sampler);
            double sum = 0;
            for (int i = 0; i < 16; ++i) {
                sampler.start_sample(uint64_t(i));
                sum += pt.radiance(Ray{Vec3::Zero(), Vec3(0.1, 0.2, -1).normalized()}, rng)[1];
            }
            means.add(sum / 16.0);
        }
        std::printf("path tracer, %s: %.4f +- %.4f (truth %.4f)\n", sampler_name(kind), means.mean(), means.se(), env);
        EXPECT_NEAR(means.mean(), env, 3.0 * means.se()) << sampler_name(kind);
    }
}

TEST(SamplerRender, IndependentIsTheDefaultImageAndTheOthersDiffer) {
    const std::vector<std::string> base = {"render.width=12", "render.height=12", "render.spp=4", "photons.count=5000"};
    auto with = [&](const std::vector<std::string>& extra) {
        std::vector<std::string> all = base;
        all.insert(all.end(), extra.begin(), extra.end());
        return run_image(all);
    };
    const Image plain = with({});
    const Image independent = with({"render.sampler=\"independent\"", "photons.sampler=\"independent\""});
    ASSERT_EQ(plain.rgb, independent.rgb);
    for (const char* name : {"stratified", "sobol"}) {
        const Image camera = with({std::string("render.sampler=\"") + name + "\""});
        const Image photons = with({std::string("photons.sampler=\"") + name + "\""});
        EXPECT_NE(camera.rgb, plain.rgb) << name;
        EXPECT_NE(photons.rgb, plain.rgb) << name;
        EXPECT_NE(camera.rgb, photons.rgb) << name;
    }
}

TEST(SamplerRender, SameImageOnOneAndTwoThreads) {
    for (const char* name : {"stratified", "sobol"}) {
        auto image = [&](int threads) {
            return run_image({"render.width=12", "render.height=12", "render.spp=4", "render.passes=2",
                              "photons.count=9000", std::string("render.sampler=\"") + name + "\"",
                              std::string("photons.sampler=\"") + name + "\"",
                              "render.threads=" + std::to_string(threads)});
        };
        const Image a = image(1), b = image(2);
        EXPECT_GT(a.mean(), 0.0);
        ASSERT_EQ(a.rgb, b.rgb) << name;
    }
}

TEST(SamplerRender, BadValuesAreOneClearError) {
    auto error = [](const std::string& set) {
        try {
            RunConfig::load(VPM_SOURCE_DIR "/configs/uniform_furnace.toml", {set});
        } catch (const std::exception& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    for (const char* key : {"render.sampler", "photons.sampler"}) {
        for (const char* bad : {"\"halton\"", "3", "\"\""}) {
            const std::string e = error(std::string(key) + "=" + bad);
            EXPECT_NE(e.find(std::string(key).substr(std::string(key).find('.') + 1)), std::string::npos) << e;
            for (const char* allowed : {"independent", "stratified", "sobol"})
                EXPECT_NE(e.find(allowed), std::string::npos) << key << "=" << bad << ": " << e;
        }
    }
}
