#pragma once
// Reading an object-to-world transform from a config sub-table:
//
//   | key       | type                        | default   | meaning                          |
//   |-----------|-----------------------------|-----------|----------------------------------|
//   | scale     | number or [sx, sy, sz], > 0 | 1         | scale about the origin           |
//   | rotate    | [ax, ay, az, degrees]       | none      | rotation about axis (non-zero)   |
//   | translate | [x, y, z]                   | [0, 0, 0] | translation                      |
//
// Applied in the order scale, rotate, translate: M = T * R * S. An absent table is the identity.
#include <Eigen/Geometry>

#include "config/params.h"

namespace vpm {

Eigen::Affine3d read_transform(Params& table);

}  // namespace vpm
