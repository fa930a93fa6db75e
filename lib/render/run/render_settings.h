#pragma once
// How the image of a run is made, whatever the integrator: the [render] table's film, sampling
// and output keys. (max_depth and rr_depth are the walk's: transport/walk_settings.h; `integrator`
// picks an entry of render/integrator_registry.h.)
//
//   | key      | default          | meaning                                                  |
//   |----------|------------------|----------------------------------------------------------|
//   | width    | 256              | pixels                                                   |
//   | height   | 256              | pixels                                                   |
//   | spp      | 16               | samples per pixel                                        |
//   | seed     | 1                | the same image on any thread count                       |
//   | threads  | 0                | worker threads; 0: all cores                             |
//   | output   | "out/render.exr" | relative to the working directory                        |
//   | exposure | 0                | PNG preview only: pixel * 2^exposure                     |
//   | passes   | 1                | independent passes (a fresh photon map each), the image  |
//   |          |                  | is their mean; each renders spp / passes samples         |
//   | time_limit | 0              | seconds; > 0: passes go on (beyond `passes`) while the   |
//   |          |                  | next one is expected to end within it; 0: off (records   |
//   |          |                  | stay bounded: render/run/run_stats.h PassSummary)            |
//   | time_limit_passes | 0       | with time_limit: the passes to render, not read from the |
//   |          |                  | clock (a run record sets it to the passes its time limit |
//   |          |                  | took, so that the record renders the same image); 0: by  |
//   |          |                  | the clock                                                |
//   | first_pass | 0              | index of this run's first pass: machines rendering       |
//   |          |                  | passes 0..7 and 8..15 merge (vpm merge) into the 16-pass |
//   |          |                  | image                                                    |
//   | sampler  | "independent"    | camera samples: "independent", "stratified" or "sobol"   |
//   |          |                  | (core/sampling/sampler.h, docs/stratified_sampling.md)            |
//   | crop     | [] (whole image) | [x0, y0, x1, y1]: only these pixels (half-open, row 0 at |
//   |          |                  | the top) are rendered, the rest stay black; each keeps   |
//   |          |                  | the value it has in the whole image                      |
#include <cstdint>
#include <string>

#include "core/sampling/sampler.h"

namespace vpm {

class Params;

// Passes a run may render, first_pass included: pass indices stay ints (render.first_pass, vpm merge),
// so a time limit stops before INT_MAX passes.
constexpr int64_t kMaxRunPasses = 2147483647;

struct RenderSettings {
    int width = 256;
    int height = 256;
    int spp = 16;
    uint64_t seed = 1;
    int threads = 0;
    std::string output = "out/render.exr";
    double exposure = 0.0;
    int passes = 1;
    double time_limit = 0.0;
    int64_t time_limit_passes = 0;
    int first_pass = 0;
    SamplerKind sampler = SamplerKind::independent;
    // render.crop: the pixels rendered, half-open; the whole image unless set.
    int crop_x0 = 0, crop_y0 = 0, crop_x1 = 0, crop_y1 = 0;
    bool cropped() const { return crop_x0 > 0 || crop_y0 > 0 || crop_x1 < width || crop_y1 < height; }
    double rendered_pixels() const { return double(crop_x1 - crop_x0) * double(crop_y1 - crop_y0); }
    int spp_per_pass() const { return spp / passes; }
    // Reads the keys above from [render]; throws ConfigError (also for an image that cannot fit in memory).
    static RenderSettings read(Params& render);
};

}  // namespace vpm
