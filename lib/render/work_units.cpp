#include "render/work_units.h"

#include "scene/media/homogeneous_medium.h"

namespace vpm {

WorkUnits work_units(const Scene& scene, int k) {
    bool grids = false;   // tracking in grids walks a DDA and takes null collisions; homogeneous media are closed forms
    for (const auto& m : scene.media) grids = grids || !dynamic_cast<const HomogeneousMedium*>(m.get());
    WorkUnits w;
    // Fitted to 10 cells x 2 forced gathers (BENCHMARKS.md section 11.7; 1 thread): homogeneous
    // media within 0.65-1.05x of the render time per sample in 9 of 10, grids within 0.4-0.7x in 8
    // of 10 (a tracked segment's cost in a grid varies with its null collisions, which are not
    // counted: the thin blob's collision gather is 4x cheaper than counted). A query in a grid
    // costs twice one in a homogeneous medium (its ball extinction reads the grid).
    w.query = (grids ? 2.0 : 1.0) * (700.0 + 280.0 * double(k));
    w.ray = grids ? 1000.0 : 3000.0;
    w.lookup = grids ? 100.0 : 30.0;
    w.collision = grids ? 1500.0 : 1000.0;
    w.path = grids ? 1500.0 : 1000.0;
    w.stored = 1000.0;
    return w;
}

}  // namespace vpm
