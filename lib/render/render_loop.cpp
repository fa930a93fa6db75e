#include "render/render_loop.h"

#include <atomic>

#include <tbb/blocked_range2d.h>
#include <tbb/parallel_for.h>
#include <tbb/task_group.h>

#include "core/progress.h"

namespace vpm {

Image render_image(const Camera& camera, const Integrator& integrator, const RenderOptions& o, RenderStats& stats) {
    Image image(o.width, o.height);
    std::atomic<uint64_t> nonfinite{0};
    Progress progress("render", uint64_t(o.height), o.progress);
    const Timer timer;
    tbb::parallel_for(tbb::blocked_range<int>(0, o.height, 1), [&](const tbb::blocked_range<int>& rows) {
        for (int y = rows.begin(); y != rows.end(); ++y) {
            // A cancelled task group (the Python module's Ctrl-C) stops at the next row; the caller
            // discards the image. A range may hold many rows, so checking between ranges is not enough.
            if (tbb::is_current_task_group_canceling()) return;
            for (int x = 0; x < o.width; ++x) {
                const uint64_t pixel = uint64_t(y) * uint64_t(o.width) + uint64_t(x);
                Rng rng(o.seed, pixel + o.stream_offset * uint64_t(o.width) * uint64_t(o.height));
                Rgb sum = Rgb::Zero();
                uint64_t bad = 0;
                for (int s = 0; s < o.spp; ++s) {
                    const double jx = rng.uniform(), jy = rng.uniform();
                    const Rgb l = integrator.radiance(camera.generate_ray(x + jx, y + jy), rng);
                    if (all_finite(l)) sum += l;
                    else ++bad;
                }
                image.set(x, y, sum / double(o.spp));
                if (bad) nonfinite += bad;
            }
            progress.advance();
        }
    });
    progress.done();
    stats.samples = uint64_t(o.width) * uint64_t(o.height) * uint64_t(o.spp);
    stats.nonfinite_samples = nonfinite.load();
    stats.seconds = timer.seconds();
    return image;
}

}  // namespace vpm
