#pragma once
// The region the camera sees: a box around where camera rays first meet a medium (a real collision,
// sampled) or a surface. Lights at infinity aim part of their photons at it (emission_bounds.h),
// because in a scene much larger than what the camera looks at, photons spread over the whole
// scene almost never land where the camera's estimates gather (the plume scaled by 1e6
// with the camera unchanged rendered 14% dark). Deterministic: fixed rays, its own seed.
#include "core/math.h"

namespace vpm {

class Scene;

constexpr int kCameraRegionRays = 1024;
// The box of the camera points grows by this fraction of its diagonal on every side: light
// scattered into the seen region comes from around it.
constexpr double kCameraRegionMargin = 0.25;

// Empty when no camera ray meets anything.
Bounds3 camera_seen_region(const Scene& scene);

}  // namespace vpm
