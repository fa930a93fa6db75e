#pragma once
// What the beam gather (render/photon_map/gathers/point_beam_gather.h) built and answered in a run: its memory beside the
// point map's, the build time of the radii and the BVH, and queries against photons crossed.
#include <cstdint>

#include "render/run/stats_section.h"

namespace vpm {

struct PointBeamGatherStats : StatsSectionOf<PointBeamGatherStats> {
    uint64_t k = 0;                  // photons.beam_k
    uint64_t photons = 0;            // photons with a finite radius (in the BVHs)
    uint64_t regions = 1;            // BVHs: one per region of a scene with glass shapes
    uint64_t bvh_bytes = 0;          // the BVH (balls + nodes; the radii live in its balls) and, with a
                                     // medium that has a jump, 4 bytes per photon of ball extinction
    double bvh_bytes_per_photon = 0.0;
    double map_bytes_per_photon = 0.0;   // the kd-tree map's, for comparison
    double total_bytes_per_photon = 0.0; // map + BVH: what the beam gather keeps in memory
    double radii_seconds = 0.0;      // wall time, summed over passes
    double bvh_seconds = 0.0;
    uint64_t queries = 0;            // camera segments answered by one BVH query
    uint64_t crossed = 0;            // photon discs they crossed
    uint64_t tracking_lookups = 0;   // sigma_t lookups of the ratio tracking in non-homogeneous media

    // Adds an earlier pass's run totals (the fields "summed over passes" and the query counts); the
    // sizes stay this pass's.
    void add_run_totals(const PointBeamGatherStats& earlier);
    void write(RunRecord& record) const override;   // photons.beam.*
};

}  // namespace vpm
