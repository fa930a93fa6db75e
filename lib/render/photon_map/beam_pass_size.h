#pragma once
// Photons and camera samples per pass for the segment gathers under render.time_limit: photons.gather
// = "photon_beams" (docs/photon_beams.md, "Time limits") and "point_beam" (docs/beam_estimate.md). A
// pass cannot be cut short, and such a pass is dominated by costs that grow faster than its photons:
// the query of every camera segment (its crossing tests grow with the beams or discs: the k-th width
// or radius shrinks more slowly than their number grows, and a long segment opens every box it
// pierces) and, for sample-point widths, each beam's own k-nearest query. So the pass is
// sized from counted work, never from the clock: two pilot maps at N_L / 4 and N_L photons are traced,
// built and queried by a probe of camera paths, each count per photon or per sample read at both
// sizes, and its growth with the photons fitted as a power (within [0, 1] per photon or query) and
// extrapolated. The chosen pass costs at most (budget - pilots) / kBeamPlanMinPasses work units; the
// clock then decides only how many such passes fit (render/run/run.cpp).
#include <cstdint>

#include "render/plan/pass_plan.h"
#include "render/plan/work_units.h"

namespace vpm {

// Passes a limit holds at least, counted on one core. 4, not the point gathers' kPlanMinPasses = 2:
// the counted units matched the user CPU time of glass_sphere_fog, plume_glass_prism and thin_cube
// (0.7-1.1x), but a loaded machine gives a 2-thread run a fraction of a core, and at 2 the first pass
// ran 1.3-1.6x past an 8-s limit at load 15-19 on 2 cores (docs/photon_beams.md, "Time limits").
constexpr double kBeamPlanMinPasses = 4.0;

// Counts of one pilot: a map of `photons` emitted photons, built, and a probe of camera samples.
// point_beam: its photon discs are the "beams" (each a k-nearest query for its radius), one BVH item
// each, and the discs a segment crosses its crossing tests.
struct BeamPilotCounts {
    double photons = 0.0;          // emitted
    double beams = 0.0;            // beams (point_beam: discs) in the BVH
    double pieces = 0.0;           // the camera BVH's items (long beams as pieces)
    double width_tests = 0.0;      // sample_point: crossing tests of the widths' queries (0: balloon)
    double collisions = 0.0;       // real medium collisions of the photon walks
    double surface_stored = 0.0;   // surface photons stored (kd-tree build)
    double samples = 0.0;          // the probe's camera samples
    double beam_queries = 0.0;     // the probe's segment queries of the beams
    double beam_tests = 0.0;       // and their crossing tests
    CountedOperations camera;      // the probe's other camera operations (kNN queries, rays, lookups)
};

// Work units (nanoseconds of one core, as render/plan/work_units.h) of the beams' own operations.
struct BeamWorkUnits {
    double query = 0.0;        // a camera segment's beam query: traversal set-up, sort, transmittance walk
    double test = 0.0;         // a crossing test of a camera segment's query (with its share of the traversal)
    double width_test = 0.0;   // a crossing test of a sample-point width's query
    double beam = 0.0;         // a beam recorded and its width kept (point_beam: a disc and its radius query)
    double piece = 0.0;        // a BVH item built
};
BeamWorkUnits beam_work_units();
// point_beam's: a disc's radius is a k-nearest query at photons.beam_k over the map (`radius_query`:
// query_price of work_units at beam_k over the largest map considered, so smaller maps err short).
BeamWorkUnits point_beam_work_units(double radius_query);

// The least growth of the crossing tests per camera query assumed beyond the pilots. Photon beams:
// N^0.5 (measured from 12,500 to 400,000 photons in glass_sphere_fog: N^0.3-0.8, while between the
// small pilots it reads near 0). point_beam: N^(1/3), the discs a segment crosses at uniform density
// (N discs of radius ~N^(-1/3): N r^2), read N^0.32 in glass_sphere_fog from 25,000 to 100,000 photons.
constexpr double kLeastBeamTestGrowth = 0.5;
constexpr double kLeastDiscTestGrowth = 1.0 / 3.0;
// The least growth of the width tests per beam beyond the pilots: sample-point widths N^0.75 (between
// pilots of 1,024 and 4,096 photons it reads near 0; from 12,500 to 50,000 photons N^0.77); density
// widths 0 (a fixed number of neighbours per beam; the log N of the tree is left out).
constexpr double kLeastWidthGrowth = 0.75;
constexpr double kLeastDensityWidthGrowth = 0.0;
// photon_beams' least samples per pass: the camera's noise, not the beams', dominates a pass of
// 1 spp on the caustic scenes (docs/photon_beams.md, "Density widths").
constexpr int kBeamLeastSpp = 4;

struct BeamPassInputs {
    BeamPilotCounts small, large;   // the pilots, small.photons < large.photons
    WorkUnits units;
    BeamWorkUnits beam_units;
    double pixels = 0.0;
    int64_t count = 0;              // photons.count (or its default): the largest N considered
    int spp = 1;                    // samples per pass as configured: the largest S considered
    bool size_photons = false;      // false: N stays count
    bool size_samples = false;      // false: S stays spp
    double least_test_growth = kLeastBeamTestGrowth;   // kLeastDiscTestGrowth for point_beam
    double least_width_growth = kLeastWidthGrowth;     // kLeastDensityWidthGrowth for density widths
    // Where both N and S are sized: move work from photons to camera samples until the photon side
    // holds at most half of the pass (photon_beams; point_beam keeps the largest N).
    bool balance_camera = false;
    // Samples per pass the sizing starts from where it sizes S (at most spp): photons are halved
    // until a pass of least_spp fits, then S doubles while it fits. photon_beams: kBeamLeastSpp.
    int least_spp = 1;
    double budget = 0.0;            // render.time_limit in work units (kWorkUnitsPerSecond per second)
};

struct BeamPassSize {
    int64_t count = 0;             // N
    int spp = 1;                   // S
    double pass_units = 0.0;       // the projected work of one pass of (N, S)
    double map_units = 0.0;        // of which the photon pass, BVH and widths
    double pilot_units = 0.0;      // the pilots' own work
    double pass_budget = 0.0;      // what a pass may cost: (budget - pilots) / kBeamPlanMinPasses
    double test_growth = 0.0;      // fitted exponent: camera crossing tests per query ~ N^test_growth
    double width_growth = 0.0;     // width tests per beam ~ N^width_growth
    bool fits = true;              // pass_units <= pass_budget
};

// Work units of one pilot (its map, build and probe).
double beam_pilot_units(const BeamPilotCounts& c, const WorkUnits& w, const BeamWorkUnits& b);

// The projected work units of a pass of N photons and S samples per pixel.
double beam_pass_units(const BeamPassInputs& in, double n, double s, double* map_units = nullptr);

// The largest N (count / 2^i, down to the small pilot's photons) with S = 1 (or the pinned S) that
// fits, then the largest S (powers of two up to spp) that still fits at that N; pinned sizes stay.
BeamPassSize size_beam_pass(const BeamPassInputs& in);

}  // namespace vpm
