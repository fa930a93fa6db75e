#pragma once
// The light types and their factory. Parameters of each [[lights]] table:
//
//   type          keys (defaults)                                   emits
//   "point"       position, intensity (W/sr, rgb)                   uniformly in all directions
//   "spot"        position, look_at, intensity, cone_angle (deg,    uniformly inside the cone
//                 half-angle in (0, 180], default 30)
//   "directional" direction (travel direction), irradiance (W/m^2)  parallel light
//   "quad"        center, u, v (half edges: corners center +- u +- v, one-sided Lambertian emitter on
//                 as for quad shapes), radiance, two_sided (false)  the side of u x v
//   "environment" radiance                                          constant radiance from every direction
//
// Area lights are not geometry: camera and scattered rays pass through them (they are seen
// only through next-event estimation). Environment radiance is seen by camera rays that escape.
#include <memory>

#include "scene/light.h"
#include "scene/params.h"

namespace vpm {

std::unique_ptr<Light> make_light(Params& p);

}  // namespace vpm
