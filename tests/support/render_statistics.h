#pragma once
// Helpers shared by the statistical renderer tests: the mean green value of a rendered image
// (asserting that no sample was non-finite); the running mean is in sample_statistics.h.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "render/run/render_loop.h"
#include "render/run/run.h"
#include "sample_statistics.h"
#include "render/run/run_config.h"

namespace vpm::test {

// Mean of the green channel over an image rendered with the config's size and camera.
inline double image_mean(const RunConfig& config, const Integrator& integrator, uint64_t seed, int spp) {
    RenderOptions o;
    o.width = config.render.width;
    o.height = config.render.height;
    o.spp = spp;
    o.seed = seed;
    o.progress = false;
    RenderStats stats;
    const Image image = render_image(config.scene->camera, integrator, o, stats);
    EXPECT_EQ(stats.nonfinite_samples, 0u);
    double m = 0;
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x) m += image.at(x, y)[1];
    return m / double(image.width * image.height);
}

// Mean image value (all channels) over `repeats` independent runs of `config` (stream offsets 0 ..
// repeats-1: independent photon maps and camera samples), asserting no non-finite sample.
inline Sample repeated_run_brightness(const RunConfig& config, int repeats) {
    Sample brightness;
    for (int r = 0; r < repeats; ++r) {
        RunOptions o;
        o.progress = false;
        o.stream_offset = uint64_t(r);
        const RunResult result = run(config, o);
        EXPECT_EQ(result.stats.render.nonfinite_samples, 0u);
        brightness.add(result.image.mean());
    }
    return brightness;
}

// Mean image value (all channels) over the passes of one run of `config` (render.passes): each pass
// has its own photon map and camera samples, so each pass's image mean is an independent sample.
inline Sample pass_brightness(const RunConfig& config) {
    RunOptions o;
    o.progress = false;
    const RunResult result = run(config, o);
    EXPECT_EQ(result.stats.render.nonfinite_samples, 0u);
    Sample brightness;
    for (const auto& pass : result.stats.passes) brightness.add(pass.image_mean);
    EXPECT_EQ(uint64_t(brightness.n), result.stats.pass_summary.count) << "more passes than the run records";
    return brightness;
}

}  // namespace vpm::test
