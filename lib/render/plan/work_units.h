#pragma once
// Work units per counted operation for the photon map's automatic choices (render/plan/pass_plan.h):
// the costs come from counts, never from the clock, so a seed gives the same choices on any
// machine. Units are nanoseconds of one core of the development machine, fitted to the render
// and photon-pass phase times of forced-gather runs over matrix cells (docs/studies/auto_plan.md section 11.7);
// only their ratios matter.
#include "scene/scene.h"

namespace vpm {

struct WorkUnits {
    double query = 0.0;       // a kNN query whose estimate is used (grows with k), over kQueryReferenceStored photons
    double query_doubling = 0.0;  // added to query per doubling of the map's stored photons (query_price)
    double query_wide = 0.0;  // one whose ball exceeds max_radius_mfp: the path continues (a bounded search)
    double ray = 0.0;         // a tracked segment: free flight, shadow ray or march transmittance
    double lookup = 0.0;      // a sigma_t lookup of the ball quadrature
    double step = 0.0;        // a grid tracking step: DDA cell or tentative collision (scene/media/tracking_counter.h)
    double density_lookup = 0.0;   // a grid point density lookup of the tracking
    double cell = 0.0;        // a grid voxel cell integrated in closed form (tracking, the march's profile)
    double collision = 0.0;   // a real collision of the photon walk
    double path = 0.0;        // an emitted photon path
    double stored = 0.0;      // a stored photon (kd-tree build)
};

WorkUnits work_units(const Scene& scene, int k);

// The map size at which WorkUnits::query is the price of a query.
constexpr double kQueryReferenceStored = 16384.0;

// A used query's price over a map of `stored` photons (at least 1): the kd-tree's depth grows as
// log2 of it, so query + query_doubling x log2(stored / kQueryReferenceStored).
double query_price(const WorkUnits& w, double stored);

}  // namespace vpm
