#pragma once
// A photon beam (Jarosz et al. 2011): one free flight of a photon path inside the media's bounds,
// the segment origin + v dir, v in [0, length], carrying the photon's power along it. A "short"
// beam: it ends where the flight ends (a collision, a surface, the media's bounds), with no
// transmittance along it; the flux of many short beams through a point is the track-length
// estimate of the fluence there (docs/photon_beams.md).
#include <cstdint>

#include "core/math.h"

namespace vpm {

struct PhotonBeam {
    Vec3 origin = Vec3::Zero();
    Vec3 dir = Vec3::UnitZ();   // unit travel direction (the d_in of hg_eval)
    double length = 0.0;
    Rgb power = Rgb::Zero();
    // The walk (emitted path) whose flight this is, labelled as its photons are (PhotonInput::walk):
    // the beams of one walk share their end points, beams of different labels are independent.
    uint64_t walk = 0;
};

}  // namespace vpm
