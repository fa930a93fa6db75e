#include "render/plan/work_units.h"

#include <algorithm>
#include <cmath>

#include "scene/media/homogeneous_medium.h"

namespace vpm {

namespace {
// The query's price (docs/studies/march.md section 25): user CPU per camera sample of the forced collision
// gather and march (288 - 32 spp, 1 thread) at photons.count 1e4 .. 8e6 (116 .. 1.2e6 stored),
// per used query (scripts/query_price_fit.py): knn x factor x (1 + kQueryDoubling log2(stored / 16384)).
// The growth is small in a render, whose queries are coherent (a pixel's samples, its neighbours):
// random queries over the blob (bench/bench_query_price.cpp) grow ~10% per doubling, mostly past
// the caches (5.7 us at 1e3 stored, 7.0 at 6.6e4, 13.9 at 1e6). The factors were refitted with the
// other camera-side weights below (docs/studies/auto_plan.md section 28).
constexpr double kQueryGrids = 0.86;
constexpr double kQueryHomogeneous = 0.8;
constexpr double kQueryDoubling = 0.015;
}  // namespace

WorkUnits work_units(const Scene& scene, int k) {
    bool grids = false;   // tracking in grids walks a DDA and takes null collisions; homogeneous media are closed forms
    for (const auto& m : scene.media) grids = grids || !dynamic_cast<const HomogeneousMedium*>(m.get());
    WorkUnits w;
    // Camera side, refitted on a quiet machine (docs/studies/auto_plan.md section 28; scripts/work_units_check.py:
    // user CPU per sample of each candidate forced, 288 - 32 spp, 1 thread) over 26 grid and 16
    // homogeneous matrix cells x 3 candidates. The previous weights charged 0.31-1.82x the time in
    // grids (the march 0.42-0.60x: its optical-depth profile was not counted; the continuation 0.31x
    // in the blob at 1000, whose closed-form cells and density lookups were not) and 0.17-0.88x in
    // homogeneous media, against 1.0 for the photon pass: the plan saw camera samples half as dear
    // as photons. Now 0.67-1.50x in grids (rms log error 0.13, was 0.56) and 0.45-1.84x in homogeneous
    // media (0.28, was 0.71; the outliers are the radius-bounded searches of the dense cells, which
    // cost ~2500 ns in the march and ~1000 in the collision gather: one weight for both).
    const double knn = 700.0 + 280.0 * double(k);
    w.query = (grids ? kQueryGrids : kQueryHomogeneous) * knn;
    w.query_doubling = kQueryDoubling * w.query;
    w.query_wide = grids ? 1500.0 : 1200.0;   // a radius-bounded search whose estimate is not used
    w.ray = grids ? 210.0 : 150.0;            // homogeneous: a closed form
    w.lookup = grids ? 62.0 : 8.0;            // a sigma_t lookup of the ball quadrature
    w.step = grids ? 15.0 : 0.0;              // a DDA cell or tentative collision
    w.density_lookup = grids ? 195.0 : 0.0;   // a trilinear density lookup of the tracking
    w.cell = grids ? 189.0 : 0.0;             // a voxel cell integrated in closed form
    // Photon pass (user CPU per emitted photon, the difference of 4e5- and 1e5-photon runs over 18
    // grid and 16 homogeneous cells, scripts/work_units_check.py --photon-pass): rms log error 0.17
    // (grids) and 0.11 (homogeneous).
    w.collision = grids ? 500.0 : 435.0;
    w.path = grids ? 490.0 : 130.0;
    w.stored = grids ? 850.0 : 320.0;
    return w;
}

double query_price(const WorkUnits& w, double stored) {
    return w.query + w.query_doubling * std::log2(std::max(stored, 1.0) / kQueryReferenceStored);
}

}  // namespace vpm
