#pragma once
// Photon-beam widths fixed before the camera pass from the beams' density (photons.beam_widths =
// "density", docs/photon_beams.md): one width per beam, stored per piece of the camera BVH
// (photon/map/photon_beam_bvh.h), so that a camera segment's query is "the pieces whose cylinder of
// their own width it crosses".
//
// The beam length per unit volume lambda at a beam's middle x is estimated from the pieces'
// middles, each carrying its length: the n nearest (n = kBeamDensityNeighbours) within distance r_n
// give lambda = (the n - 1 nearer's lengths) / (4/3 pi r_n^3). The width is the u within which a segment
// of the beams' mean length L crosses k beams of an isotropic field of that density,
//
//     r = 2 k / (pi lambda L)      (crossings within r: 2 r lambda L E[sin theta], E = pi/4),
//
// at most bound(x). A width is a function of its beam and the other beams only, never of a camera
// ray, so the estimate is unbiased for the blurred field for every width (the Mecke argument of the
// sample-point form); the density only decides how wide the blur is.
#include <cstdint>
#include <functional>
#include <vector>

#include "core/math.h"
#include "photon/map/photon_beam.h"

namespace vpm {

struct BeamDensityWidths {
    std::vector<double> widths;   // one per piece, in PhotonBeamBvh's per-piece order
    uint64_t queries = 0;         // nearest-neighbour queries (one per beam)
    uint64_t bounded = 0;         // widths that took bound(x)
};

// Neighbours of the density estimate. lambda's relative noise (~1/sqrt(n)) only moves the width,
// and the query's cost grows with n (32 took twice as long as 16 on water_caustics).
constexpr size_t kBeamDensityNeighbours = 16;

// bound(x): the largest width at x (kInfinity for none). scale multiplies every width (a
// progressive pass's width scale, in (0, 1]).
BeamDensityWidths beam_density_widths(const std::vector<PhotonBeam>& beams, double max_piece, size_t k,
                                      const std::function<double(const Vec3&)>& bound, double scale = 1.0);

}  // namespace vpm
