#pragma once
// Medium types by name. Each [[media]] table names its `type`; make_medium dispatches to that
// type's factory, which reads the table's keys (each medium's header documents them):
//
//   type           file                       keys
//   "homogeneous"  homogeneous_medium.h       shape ("box": min, max | "sphere": center, radius),
//                                             sigma_t_scale, albedo, g
//   "grid"         grid_medium.h              file, grid, sigma_t_scale, albedo, g, transform
//
// A medium gives sigma_t, bounds, free-flight sampling and transmittance (scene/media/medium.h); a
// medium with a density lookup and majorants can reuse the shared tracking over a majorant walk
// instead of writing its own. Adding a medium type: one file with its Medium class and factory,
// and one line in the table in medium_registry.cpp (with its declaration beside it); docs/config.md's
// [[media]] row names it (tests/tools/registry_docs_test.cpp fails until it does).
//
// What every medium must meet (Scene::build checks what it can, with one error naming the table):
// - bounds() is a finite, non-empty box outside which sigma_t is 0: lights at infinity emit over
//   the scene bounds, and a point light aims at their centre. A medium without natural bounds
//   (a slab, a fog) bounds itself to the region the camera and lights can reach.
// - sample_free_flight, transmittance and majorant_pieces agree with sigma_t (unbiased: tested
//   per medium against closed forms in tests/scene/).
#include <memory>
#include <string>
#include <vector>

#include "scene/media/medium.h"
#include "config/params.h"

namespace vpm {

struct MediumType {
    const char* name;
    std::unique_ptr<Medium> (*create)(Params& table);   // reads its keys; the caller calls finish()
    bool uses_openvdb;                                   // for the build log and the sidecar
};

// The registered types, in registry order, and their names (core/registry.h).
const std::vector<MediumType>& medium_types();
std::vector<std::string> medium_names();

// Reads `type`, builds that medium from the rest of the table and reports unknown keys.
// `type_out`, when given, receives the registry entry used.
std::unique_ptr<Medium> make_medium(Params& table, const MediumType** type_out = nullptr);

}  // namespace vpm
