#include "render/run/render_settings.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/progress.h"
#include "core/sampling/sampler_registry.h"
#include "core/thread_limit.h"
#include "config/params.h"

namespace vpm {

RenderSettings RenderSettings::read(Params& p) {
    RenderSettings r;
    r.width = int(p.integer("width", r.width, Range::closed(1, 65536)));
    r.height = int(p.integer("height", r.height, Range::closed(1, 65536)));
    r.spp = int(p.integer("spp", r.spp, Range::closed(1, 1 << 24)));
    r.seed = uint64_t(p.integer("seed", int64_t(r.seed), Range::at_least(0)));
    r.threads = int(p.integer("threads", r.threads, Range::closed(0, kMaxThreads)));
    r.output = p.string("output", r.output);
    r.exposure = p.real("exposure", r.exposure, Range::closed(-64, 64));
    r.passes = int(p.integer("passes", r.passes, Range::closed(1, 1 << 24)));
    if (r.spp % r.passes != 0)
        p.fail("passes", "render.spp = " + std::to_string(r.spp) + " must be a multiple of passes = " +
                             std::to_string(r.passes) + " (each pass renders spp / passes samples per pixel)");
    r.time_limit = p.real("time_limit", r.time_limit, Range::closed(0.0, 1e9));
    r.first_pass = int(p.integer("first_pass", r.first_pass, Range::closed(0, 1 << 24)));
    // Pass indices stay ints (render/run/run.cpp).
    r.time_limit_passes = p.integer("time_limit_passes", r.time_limit_passes, Range::closed(0, kMaxRunPasses - r.first_pass));
    if (r.time_limit_passes > 0 && !(r.time_limit > 0))
        p.fail("time_limit_passes", "is the pass count a render.time_limit took; it needs render.time_limit > 0 (for a "
                                    "fixed pass count without a limit, set render.passes)");
    if (r.time_limit_passes > 0 && r.time_limit_passes < r.passes)
        p.fail("time_limit_passes", std::to_string(r.time_limit_passes) + " is fewer than render.passes = " +
                                        std::to_string(r.passes) + ", which a time-limited run always renders");
    r.sampler = p.choice("sampler", r.sampler, sampler_choices());
    r.crop_x1 = r.width;
    r.crop_y1 = r.height;
    const std::vector<double> crop = p.reals("crop", {}, Range::at_least(0.0));
    if (!crop.empty()) {
        const bool whole = crop.size() == 4 && std::all_of(crop.begin(), crop.end(), [](double v) { return v == std::floor(v); });
        if (!whole || !(crop[0] < crop[2] && crop[2] <= r.width && crop[1] < crop[3] && crop[3] <= r.height))
            p.fail("crop", "must be [x0, y0, x1, y1], whole pixel indices with 0 <= x0 < x1 <= width (" + std::to_string(r.width) +
                               ") and 0 <= y0 < y1 <= height (" + std::to_string(r.height) + "), half-open, row 0 at the top");
        r.crop_x0 = int(crop[0]);
        r.crop_y0 = int(crop[1]);
        r.crop_x1 = int(crop[2]);
        r.crop_y1 = int(crop[3]);
    }
    // Film accumulators are 3 doubles per pixel next to the 3-float image; refuse what cannot fit.
    const double bytes = double(r.width) * double(r.height) * 3.0 * (8.0 + 4.0);
    if (bytes > 0.8 * double(physical_memory_bytes()))
        p.fail("width", "a " + std::to_string(r.width) + "x" + std::to_string(r.height) + " image needs " +
                            std::to_string(bytes / 1e9) + " GB, more than this machine's memory");
    return r;
}

}  // namespace vpm
