#pragma once
// Scene configs compiled into the library (cmake/builtin_scenes.cpp.in), for analyses that need
// a known scene at run time without the source tree.
namespace vpm {
// The text of configs/uniform_furnace.toml: the volume furnace of the photon_pass study scenario.
const char* builtin_uniform_furnace_toml();
}  // namespace vpm
