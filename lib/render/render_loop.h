#pragma once
// Renders an image by averaging an integrator's estimates over spp jittered camera rays per pixel.
// Every pixel draws from its own Rng stream (seed, pixel index), so the image is the same for
// any thread count. Non-finite estimates are counted and left out of the average, never clamped
// or hidden: the count is returned and written to the sidecar.
#include <cstdint>

#include "render/image.h"
#include "render/integrator.h"
#include "scene/camera.h"

namespace vpm {

struct RenderStats {
    uint64_t samples = 0;
    uint64_t nonfinite_samples = 0;
    double seconds = 0.0;
    double samples_per_second() const { return seconds > 0 ? double(samples) / seconds : 0.0; }
};

struct RenderOptions {
    int width = 0, height = 0, spp = 1;
    uint64_t seed = 1;
    bool progress = true;
    // Stream offset so that independent renders (e.g. repeats) can share a seed without sharing noise.
    uint64_t stream_offset = 0;
};

Image render_image(const Camera& camera, const Integrator& integrator, const RenderOptions& options,
                   RenderStats& stats);

}  // namespace vpm
