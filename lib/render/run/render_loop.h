#pragma once
// Renders an image by averaging an integrator's estimates over spp jittered camera rays per pixel.
// Every pixel draws from its own Rng stream (seed, pixel index), so the image is the same for
// any thread count. With a sampler other than "independent" (render.sampler, core/sampling/sampler.h) that
// Rng is bound to the pixel's sample set in the pass (spp vectors): dimensions 0 and 1 place the
// sample in the pixel, the integrator's path reads the next ones.
// Non-finite estimates are counted and left out of the average, never clamped
// or hidden: the count is returned and written to the sidecar. Negative estimates (no radiance is
// negative: a wrong estimator) are kept in the average, so the mean stays the estimator's, and
// counted the same way.
#include <cstdint>
#include <iosfwd>
#include <vector>

#include "core/sampling/sampler.h"
#include "render/run/image.h"
#include "render/integrator.h"
#include "scene/camera.h"

namespace vpm {

struct RenderStats {
    uint64_t samples = 0;
    uint64_t nonfinite_samples = 0;
    uint64_t negative_samples = 0;   // finite, with a channel < 0 (kept in the average)
    double seconds = 0.0;
    double samples_per_second() const { return seconds > 0 ? double(samples) / seconds : 0.0; }
};

struct RenderOptions {
    int width = 0, height = 0, spp = 1;
    uint64_t seed = 1;
    bool progress = true;
    // Stream offset so that independent renders (e.g. repeats) can share a seed without sharing noise.
    uint64_t stream_offset = 0;
    SamplerKind sampler = SamplerKind::independent;   // render.sampler
    // render.crop: the pixels rendered (half-open); the others add nothing to the sums. The whole
    // image when x1 or y1 is 0. A pixel's streams do not depend on the window.
    int crop_x0 = 0, crop_y0 = 0, crop_x1 = 0, crop_y1 = 0;
    // Under render.time_limit, the seconds left when the go over the image starts (0: no limit).
    // Once a twentieth of the rows is done, a projected end past it is said once on `log`; the
    // go over the image is not cut short, so the image does not depend on the clock.
    double seconds_left = 0.0;
    double time_limit = 0.0;   // render.time_limit, for the message
    std::ostream* log = nullptr;
};

Image render_image(const Camera& camera, const Integrator& integrator, const RenderOptions& options,
                   RenderStats& stats);

// Renders `passes` passes in one go over the image: pass g draws exactly what render_image
// draws with stream_offset + g * pass_stride, and its pixel values, rounded to float as an Image
// stores them, are added to `sum` (3 doubles per pixel) in pass order, so the sum equals that of
// rendering the passes one by one (and one pass's sum is its image). pass_means[g] is pass g's
// mean over pixels and channels (summed by rows, in row order: independent of the thread count).
// For integrators without per-pass state (Integrator::stateless_passes); it saves the per-pass
// cost of a go over the image where a pass holds few samples (render.time_limit on a small image).
// luminance_sq (one double per pixel, may be null): each pass's squared pixel luminance is added to
// it, for the variance of the mean across passes (RunOptions::pass_variance).
void render_passes(const Camera& camera, const Integrator& integrator, const RenderOptions& options, int passes,
                   uint64_t pass_stride, std::vector<double>& sum, std::vector<double>& pass_means, RenderStats& stats,
                   std::vector<double>* luminance_sq = nullptr);

}  // namespace vpm
