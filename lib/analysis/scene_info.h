#pragma once
// What a scene config or a VDB file holds, before rendering it (`vpm info`, vpm.info): bounds,
// voxel sizes, density ranges and active voxels, the optical thickness across each medium, the
// lights and their power (Light::power: what they emit into the scene's box), the shapes, and
// what the camera sees.
//
// Optical thickness "across" a medium: the integral of sigma_t along the three axis-parallel
// lines through the centre of its world bounds, from face to face (midpoint rule, kTauSteps
// steps: exact for a homogeneous box or sphere, within the trilinear field's variation over a
// step for a grid). What the camera sees: the primary rays through up to kSeenSide x kSeenSide
// pixel centres spread over the image, each counted as meeting a medium (positive optical depth
// before any surface), a surface or area light (first), or nothing.
#include <nlohmann/json_fwd.hpp>
#include <string>

#include "render/run/run_config.h"

namespace vpm {

constexpr int kTauSteps = 4096;
constexpr int kSeenSide = 64;

// The built scene of a config (RunConfig::build), as JSON: image, world_bounds, media[],
// lights[], shapes, camera (with seen: fractions of pixels).
nlohmann::json scene_info(const RunConfig& config);

// Every float/double grid of a VDB file: index box, voxel size, world bounds, active voxels,
// density range, optical thickness across at sigma_t_scale = 1, where the density is
// (density_extent.h: density_bounds, the voxels > 0; mass_bounds, the box holding nearly all of it,
// and mass_inside, its share); and a suggested camera (on +z of the mass bounds' centre, fov 40
// degrees, their bounding sphere filling the view). Throws FileError.
nlohmann::json vdb_info(const std::string& path);

// The JSON of scene_info or vdb_info as indented text for a terminal.
std::string info_text(const nlohmann::json& info);

}  // namespace vpm
