#pragma once
// Self-intersection tolerances, relative to the coordinates of the hit and the ray at hand (never
// to the scene's extent: one large shape must not blur a small one). Positions are double, so
// their rounding is a few units of DBL_EPSILON times the largest coordinate involved.
//   kStartTolerance  a surface within this of a ray's origin (times the origin's and the surface's
//                    coordinates), across the surface, is the one the ray starts on (surfaces.cpp)
//   kSpawnOffset     how far a spawned ray's origin leaves its surface (times the hit's
//                    coordinates): 16 x the start tolerance, so the new origin is clearly off it
//   kFloatStart      Embree's float tnear (times the origin's float coordinates): a few float
//                    units, so that most float self-hits are never reported
#include <cfloat>

#include "core/math.h"

namespace vpm {

constexpr double kStartTolerance = 64.0 * DBL_EPSILON;
constexpr double kSpawnOffset = 1024.0 * DBL_EPSILON;
constexpr double kFloatStart = 16.0 * FLT_EPSILON;

// Largest absolute coordinate: the scale of a point's rounding.
inline double magnitude(const Vec3& p) { return p.cwiseAbs().maxCoeff(); }

}  // namespace vpm
