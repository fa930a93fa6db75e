#pragma once
// A photon map split into `parts` maps by walk group (photon.h: the photons of one emitted path
// share a group, path index mod kWalkGroups), each photon's power times `parts`. The parts hold
// disjoint sets of whole paths, so they are independent maps of count / parts photons each with
// the same expected density: the difference of two parts' estimates measures the map's own noise
// (render/gather_pilot.h). `parts` must divide kWalkGroups. In each part the photons' groups are
// renumbered g / parts, whole walks still sharing one, so that both walk halves of
// photon/estimate/group_estimate.h are present in every part (for parts <= kWalkGroups / 2).
#include <vector>

#include "photon/map/photon_map.h"

namespace vpm {

std::vector<PhotonMap> split_by_walk_group(const PhotonMap& map, int parts);

}  // namespace vpm
