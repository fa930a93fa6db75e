#pragma once
// What the photon-beams gather (render/photon_map/gathers/photon_beams_gather.h) built and answered in a run.
#include <cstdint>
#include <string>

#include "render/run/stats_section.h"

namespace vpm {

struct PhotonBeamsGatherStats : StatsSectionOf<PhotonBeamsGatherStats> {
    std::string widths;              // photons.beam_widths: "balloon" | "sample_point" | "density"
    uint64_t k = 0;                  // photons.k of the last pass (photons.schedule may shrink it)
    uint64_t recorded = 0;           // beams the photon pass recorded (last pass)
    uint64_t beams = 0;              // beams in the BVHs (last pass)
    uint64_t regions = 1;            // BVHs: one per region of a scene with glass shapes (last pass)
    uint64_t pieces = 0;             // the BVH's items: long beams cut into pieces (last pass)
    double piece_length = 0.0;       // the longest piece (PhotonBeamBvh::automatic_piece_length)
    uint64_t bvh_bytes = 0;          // BVH items + nodes + the beams' records (last pass)
    double bytes_per_beam = 0.0;
    double widths_seconds = 0.0;     // sample_point: each beam's k nearest; density: the pieces' density (summed over passes)
    uint64_t widths_tested = 0;      // sample_point: crossing tests of those queries; density: neighbours sought (summed over passes)
    double bvh_seconds = 0.0;        // summed over passes
    uint64_t queries = 0;            // camera segments answered by one BVH query
    uint64_t crossed = 0;            // beams weighed (within the width, feet inside both segments)
    uint64_t tested = 0;             // beam-segment crossing tests in the BVH's leaves (cost)
    uint64_t starved = 0;            // balloon: segments crossed by fewer than k - 1 beams within the bound (the camera path goes on there)
    uint64_t band_zeros = 0;         // balloon: segments crossed by exactly k - 1 within the mfp bound (0: bounded_radius.h's split)
    // Rules that would leave light out, counted (last pass). sample_point widths of beams crossed by
    // fewer than k others: bounded (photons.max_radius), extrapolated (u_m k / m from the m < k
    // found) or typical (none found: the median width); density: pieces whose width took the bound;
    // beams_left_out: non-finite or empty flights.
    uint64_t widths_bounded = 0;
    uint64_t widths_extrapolated = 0;
    uint64_t widths_typical = 0;
    uint64_t beams_left_out = 0;
    uint64_t tracking_lookups = 0;   // sigma_t lookups of the camera transmittance's ratio tracking

    // Adds an earlier pass's run totals (the fields "summed over passes" and the query counts); the
    // sizes stay this pass's.
    void add_run_totals(const PhotonBeamsGatherStats& earlier);
    void write(RunRecord& record) const override;   // photons.photon_beams.*
};

}  // namespace vpm
