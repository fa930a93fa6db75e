#include "render/work_units.h"

#include <algorithm>
#include <cmath>

#include "scene/media/homogeneous_medium.h"

namespace vpm {

namespace {
// The query's price (BENCHMARKS.md section 25): user CPU per camera sample of the forced collision
// gather and march (288 - 32 spp, 1 thread) on blob tau 1, 3, 10, box tau 1 and plume tau 1 at
// photons.count 1e4 .. 8e6 (116 .. 1.2e6 stored), less the other counted terms at their prices,
// per used query (scripts/query_price_fit.py): fitted as knn x factor x (1 + kQueryDoubling log2(stored / 16384)); rms log
// (counted / real) over those 27 runs 0.250 with the flat 0.75 / 0.5 x knn, 0.134 with this. The
// growth is small in a render, whose queries are coherent (a pixel's samples, its neighbours):
// random queries over the blob (bench/bench_query_price.cpp) grow ~10% per doubling, mostly past
// the caches (5.7 us at 1e3 stored, 7.0 at 6.6e4, 13.9 at 1e6).
constexpr double kQueryGrids = 0.52;
constexpr double kQueryHomogeneous = 0.435;
constexpr double kQueryDoubling = 0.015;
}  // namespace

WorkUnits work_units(const Scene& scene, int k) {
    bool grids = false;   // tracking in grids walks a DDA and takes null collisions; homogeneous media are closed forms
    for (const auto& m : scene.media) grids = grids || !dynamic_cast<const HomogeneousMedium*>(m.get());
    WorkUnits w;
    // Refitted (BENCHMARKS.md section 11.8; 1 thread, 32 spp, load 6): render ns per sample of 8 grid
    // and 6 homogeneous matrix cells x 2 forced gathers against the pilot's counts, within 0.61-1.28x
    // (grids) and 0.55-1.68x (homogeneous; the previous weights 2-19x over). A query whose ball
    // is cut by max_radius_mfp and continues the path is a short radius-bounded search: apart from
    // the used ones (the dense boxes' queries are all of that kind: 5.8x over when counted alike).
    // Grid tracking steps (DDA cells and tentative collisions, scene/media/tracking_counter.h) are
    // counted; the fit cannot tell their weight from 0 (1.6-38 per sample in these cells: rms log
    // error 0.1996 at 0, 0.2002 at 10), so 10, a few random draws and a density lookup.
    const double knn = 700.0 + 280.0 * double(k);
    w.query = (grids ? kQueryGrids : kQueryHomogeneous) * knn;
    w.query_doubling = kQueryDoubling * w.query;
    w.query_wide = 200.0;
    // A tracked segment in homogeneous media is a closed form: 105-130 ns (user CPU per sample of the
    // path-traced continuation over its counted segments: box tau 10 117, sphere tau 1 129, sphere tau
    // 100 105; BENCHMARKS.md section 19). 500 charged the continuation 2.6-6.4x (median 4.3x) its
    // time and the collision gather 1.3x, against the march's 1.2x: the plan's choice leaned to the march.
    w.ray = grids ? 300.0 : 120.0;
    w.lookup = grids ? 40.0 : 5.0;
    w.step = grids ? 10.0 : 0.0;
    // Photon pass (trace and kd-tree build ns per emitted photon, the same runs): within 0.79-1.19x.
    w.collision = grids ? 1000.0 : 400.0;
    w.path = grids ? 300.0 : 100.0;
    w.stored = 500.0;
    return w;
}

double query_price(const WorkUnits& w, double stored) {
    return w.query + w.query_doubling * std::log2(std::max(stored, 1.0) / kQueryReferenceStored);
}

}  // namespace vpm
