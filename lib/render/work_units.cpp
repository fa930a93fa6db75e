#include "render/work_units.h"

#include "scene/media/homogeneous_medium.h"

namespace vpm {

WorkUnits work_units(const Scene& scene, int k) {
    bool grids = false;   // tracking in grids walks a DDA and takes null collisions; homogeneous media are closed forms
    for (const auto& m : scene.media) grids = grids || !dynamic_cast<const HomogeneousMedium*>(m.get());
    WorkUnits w;
    w.query = 700.0 + 280.0 * double(k);
    w.ray = grids ? 1000.0 : 100.0;
    w.lookup = 50.0;
    w.collision = grids ? 500.0 : 150.0;
    w.path = 300.0;
    w.stored = 1000.0;
    return w;
}

}  // namespace vpm
