#include "scene/media/optical_depth_profile.h"

#include <algorithm>
#include <cmath>

namespace vpm {

double OpticalDepthProfile::invert(double tau, size_t& cursor) const {
    // Skip the pieces that end at or before tau; the last piece takes any rounding at the end.
    while (cursor + 1 < pieces_.size() && !(tau < pieces_[cursor].before + pieces_[cursor].depth)) ++cursor;
    const Piece& p = pieces_[cursor];
    // In density units, finite even where the piece's optical depth is not.
    const double u = p.cubic.invert_integral(std::max(0.0, tau - p.before) / scale_ / p.len);
    return p.ta + u * p.len;
}

}  // namespace vpm
