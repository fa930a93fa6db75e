#pragma once
// One of the repository's procedural VDB media (media/NAME.vdb) as a scene's media list, at
// sigma_t_scale 1, albedo 0.9 and g 0: the grid the ball-extinction and mass-lattice tests read.
#include <memory>
#include <string>
#include <vector>

#include "io/vdb_io.h"
#include "scene/media/grid_medium.h"

namespace vpm::test {

inline std::vector<std::unique_ptr<Medium>> repo_grid_medium(const std::string& name) {
    std::vector<std::unique_ptr<Medium>> media;
    media.push_back(std::make_unique<GridMedium>(load_vdb_density(std::string(VPM_SOURCE_DIR "/media/") + name + ".vdb"), 1.0,
                                                 Rgb::Constant(0.9), 0.0));
    return media;
}

}  // namespace vpm::test
