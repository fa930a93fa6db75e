#include "render/run/render_loop.h"

#include <algorithm>
#include <atomic>
#include <ostream>
#include <sstream>
#include <vector>

#include <tbb/blocked_range2d.h>
#include <tbb/parallel_for.h>
#include <tbb/task_group.h>

#include "core/error.h"
#include "core/sampling/hashed_permutation.h"
#include "core/progress.h"

namespace vpm {

namespace {
constexpr uint64_t kCameraSalt = 0x63616d657261ULL;   // camera sample sets apart from photon sets
// Rows go in a fixed pseudo-random order, so that the rows done at any moment are a fair sample of
// the image's cost and the progress bar's ETA holds where rows differ in cost (sky above a dense
// medium); each row's pixels draw the same streams in any order, so the image does not change.
constexpr uint64_t kRowOrderKey = 0x726f776f72646572ULL;
}  // namespace

Image render_image(const Camera& camera, const Integrator& integrator, const RenderOptions& o, RenderStats& stats) {
    // One pass of render_passes: its sum holds each pixel's value exactly as the float image does.
    std::vector<double> sum(size_t(o.width) * size_t(o.height) * 3, 0.0), means;
    render_passes(camera, integrator, o, 1, 0, sum, means, stats);
    Image image(o.width, o.height);
    for (size_t i = 0; i < sum.size(); ++i) image.rgb[i] = float(sum[i]);
    return image;
}

void render_passes(const Camera& camera, const Integrator& integrator, const RenderOptions& o, int passes,
                   uint64_t pass_stride, std::vector<double>& sum, std::vector<double>& pass_means, RenderStats& stats,
                   std::vector<double>* luminance_sq) {
    const size_t pixels = size_t(o.width) * size_t(o.height), rows = size_t(o.height);
    const bool whole = o.crop_x1 == 0 || o.crop_y1 == 0;
    const int x0 = whole ? 0 : o.crop_x0, x1 = whole ? o.width : o.crop_x1;
    const int y0 = whole ? 0 : o.crop_y0, y1 = whole ? o.height : o.crop_y1;
    if (x0 < 0 || x1 > o.width || x0 >= x1 || y0 < 0 || y1 > o.height || y0 >= y1)
        throw Error("render_passes: the crop window must lie in the image");
    if (sum.size() != 3 * pixels) throw Error("render_passes: the sum must hold 3 doubles per pixel");
    if (luminance_sq && luminance_sq->size() != pixels) throw Error("render_passes: luminance_sq must hold 1 double per pixel");
    std::vector<double> row_sums(size_t(passes) * rows, 0.0);   // [pass][row]
    std::atomic<uint64_t> nonfinite{0}, negative{0};
    Progress progress("render", uint64_t(o.height), o.progress);
    const Timer timer;
    // The projected end of this go over the image against the time limit: said once, from the
    // rows done so far (a message only; what is rendered does not depend on it).
    const bool watch_limit = o.seconds_left > 0.0 && o.log;
    std::atomic<uint64_t> rows_done{0};
    std::atomic<bool> warned{false};
    auto warn_if_projected_past_limit = [&] {
        const uint64_t done = ++rows_done;
        if (done < std::max<uint64_t>(1, rows / 20) || warned.load(std::memory_order_relaxed)) return;
        const double projected = timer.seconds() * double(rows) / double(done);
        if (!(projected > 2.0 * o.seconds_left) || warned.exchange(true)) return;
        std::ostringstream msg;
        msg.precision(3);
        msg << "warning: render.time_limit = " << o.time_limit << " s: this pass projects to about " << projected
            << " s (" << done << " of " << rows << " rows in " << timer.seconds()
            << " s); a pass is not cut short, so the run ends then (Ctrl-C stops it)\n";
        *o.log << msg.str() << std::flush;
    };
    tbb::parallel_for(tbb::blocked_range<int>(0, o.height, 1), [&](const tbb::blocked_range<int>& range) {
        std::vector<double> row(static_cast<size_t>(passes), 0.0);   // this row's sum per pass (written once: no false sharing)
        for (int r = range.begin(); r != range.end(); ++r) {
            const int y = int(permutation_element(uint32_t(r), uint32_t(o.height), kRowOrderKey));
            // A cancelled task group (the Python module's Ctrl-C) stops at the next row; the caller
            // discards the image. A range may hold many rows, so checking between ranges is not enough.
            if (tbb::is_current_task_group_canceling()) return;
            uint64_t bad = 0, below_zero = 0;
            std::fill(row.begin(), row.end(), 0.0);
            const bool in_crop = y >= y0 && y < y1;
            for (int x = in_crop ? x0 : x1; x < x1; ++x) {
                const uint64_t pixel = uint64_t(y) * uint64_t(o.width) + uint64_t(x);
                double* acc = &sum[3 * pixel];
                for (int g = 0; g < passes; ++g) {
                    const uint64_t stream = o.stream_offset + uint64_t(g) * pass_stride;
                    const uint64_t pixel_stream = pixel + stream * uint64_t(o.width) * uint64_t(o.height);
                    Rng rng(o.seed, pixel_stream);
                    PathSampler sampler(o.sampler, sampler_key(o.seed, pixel_stream, 0, kCameraSalt), uint64_t(o.spp));
                    if (o.sampler != SamplerKind::independent) rng.draw_from(&sampler);
                    Rgb s = Rgb::Zero();
                    for (int k = 0; k < o.spp; ++k) {
                        sampler.start_sample(uint64_t(k));
                        const double jx = rng.uniform(), jy = rng.uniform();
                        const Rgb l = integrator.radiance(camera.generate_ray(x + jx, y + jy), rng);
                        if (all_finite(l)) {
                            s += l;
                            below_zero += (l.array() < 0.0).any();
                        } else {
                            ++bad;
                        }
                    }
                    const Rgb v = s / double(o.spp);
                    double stored[3];
                    for (int c = 0; c < 3; ++c) {
                        stored[c] = double(float(v[c]));   // as Image::set stores it
                        acc[c] += stored[c];
                        row[size_t(g)] += stored[c];
                    }
                    if (luminance_sq) {   // Rec. 709 luminance, as analysis/metrics/error_metrics.h compares
                        const double y = 0.2126 * stored[0] + 0.7152 * stored[1] + 0.0722 * stored[2];
                        (*luminance_sq)[pixel] += y * y;
                    }
                }
            }
            for (int g = 0; g < passes; ++g) row_sums[size_t(g) * rows + size_t(y)] = row[size_t(g)];
            if (bad) nonfinite += bad;
            if (below_zero) negative += below_zero;
            progress.advance();
            if (watch_limit) warn_if_projected_past_limit();
        }
    });
    progress.done();
    pass_means.assign(size_t(passes), 0.0);
    for (int g = 0; g < passes; ++g) {
        double total = 0.0;
        for (size_t y = 0; y < rows; ++y) total += row_sums[size_t(g) * rows + y];
        pass_means[size_t(g)] = total / double(3 * size_t(x1 - x0) * size_t(y1 - y0));   // over the crop's pixels
    }
    stats.samples = uint64_t(x1 - x0) * uint64_t(y1 - y0) * uint64_t(o.spp) * uint64_t(passes);
    stats.nonfinite_samples = nonfinite.load();
    stats.negative_samples = negative.load();
    stats.seconds = timer.seconds();
}

}  // namespace vpm
