#pragma once
// The "exclude directly seen lights" mask of the error metrics (pixel_mask.h), from the scene: the
// pixels where a camera ray meets an area light (quad, sphere), straight or through a chain of
// mirror and glass surfaces. There a pixel holds the light's own radiance, orders of magnitude over
// the rest of the image, and its noise (a glint through glass) decides a relative error on its own.
//
// A pixel is marked where any of side x side rays through it (the centres of a regular sub-pixel
// grid) reaches an area light; at a dielectric both the reflected and the refracted ray are
// followed, up to kSeenLightSpecularDepth specular events. Media are not: a light behind fog still
// dominates its pixel. Lights at infinity (environment) and delta lights (point, spot, directional)
// are never seen as a shape, so they mark nothing. Deterministic: no random numbers.
#include <cstdint>
#include <string>
#include <vector>

#include "analysis/metrics/pixel_mask.h"
#include "scene/scene.h"

namespace vpm {

constexpr int kSeenLightSpecularDepth = 8;
constexpr int kSeenLightSubpixels = 4;   // side of the sub-pixel grid

// One byte per pixel of a width x height image, row 0 at the top: 1 where an area light is seen.
// The image may have another size than the scene's camera but must have its aspect ratio (the rays
// are the camera's, scaled); throws vpm::Error otherwise, naming both sizes.
std::vector<uint8_t> seen_light_pixels(const Scene& scene, int width, int height, int side = kSeenLightSubpixels);

// Leaves out of `mask` the pixels where `scene` shows an area light; `name` (the config file) goes
// into the mask's description.
void exclude_seen_lights(PixelMask& mask, const Scene& scene, const std::string& name);

}  // namespace vpm
