#pragma once
// Memory guard and progress lines for the photon pass.
//
// The photon tracer calls PhotonTraceSettings::on_chunk after a 65536-photon pilot chunk and then
// after every ~1M photons. The guard made here projects the final number of stored photons
// (volume + surface) and photon beams from the per-emitted rates so far, and the peak memory of
// storing them and building their indices (kPeakBytesPerStoredPhoton per photon: the kd-tree;
// kPeakBytesPerBeam per beam: the beams' BVH). When that projection, or the memory already used,
// exceeds the limit (the memory this process may use, memory_limit_bytes in core/progress.h), it
// stops the pass with a vpm::Error naming photons.count,
// the projection and the largest count that fits: a clear error before the real work instead of
// std::bad_alloc or swapping. Every ten seconds it writes a progress line to the log (which, unlike the
// progress bar, also appears when stderr is not a terminal).
#include <cstdint>
#include <functional>
#include <iosfwd>

#include "photon/map/photon.h"
#include "photon/map/photon_beam_bvh.h"
#include "photon/trace/photon_tracer.h"

namespace vpm {

// Peak bytes per stored photon: the tracer's PhotonInput record, plus the map build's peak while
// the records still exist (photon_map.cpp: the compact record twice while it moves into leaf order,
// its walk id in Morton and in leaf order, the tree's permutation entry, ~4 bytes of nodes).
constexpr double kPeakBytesPerStoredPhoton = double(sizeof(PhotonInput)) + 2.0 * double(sizeof(Photon)) + 4.0 + 4.0 + 4.0 + 4.0;

// Peak bytes per photon beam: its record (reserved a tenth over the pilot's projection), its
// sample-point width, and the camera rays' BVH over its pieces (photon/map/photon_beam_bvh.h; the
// sample-point widths' own BVH of whole beams is freed before that one is built).
inline double peak_bytes_per_beam() {
    return 1.1 * double(sizeof(PhotonBeam)) + double(sizeof(double)) + PhotonBeamBvh::max_bytes_per_beam();
}

// Projected stored photons at the end of the pass, from the totals so far.
double projected_stored_photons(const PhotonTraceProgress& p);
// Projected photon beams at the end of the pass, from the totals so far.
double projected_beams(const PhotonTraceProgress& p);

// The on_chunk callback: throws vpm::Error when the projected peak exceeds limit_bytes; writes a
// progress line to *log (when not null) at most every log_interval_s seconds.
std::function<void(const PhotonTraceProgress&)> make_photon_pass_guard(double limit_bytes, std::ostream* log,
                                                                      double log_interval_s = 10.0);

}  // namespace vpm
