#include "scene/media/optical_depth_profile.h"

#include <algorithm>
#include <cmath>

namespace vpm {

bool OpticalDepthProfile::add(double ta, double tb, const tracking::CubicBernstein& cubic) {
    if (!(tb > ta)) return total_ < kEnoughDepth;
    const double depth = scale_ * (cubic.integral() * (tb - ta));
    if (depth > 0.0) {
        pieces_.push_back(Piece{ta, tb - ta, total_, depth, cubic});
        total_ += depth;
    }
    return total_ < kEnoughDepth;
}

double OpticalDepthProfile::invert(double tau, size_t& cursor) const {
    // Skip the pieces that end at or before tau; the last piece takes any rounding at the end.
    while (cursor + 1 < pieces_.size() && !(tau < pieces_[cursor].before + pieces_[cursor].depth)) ++cursor;
    const Piece& p = pieces_[cursor];
    // In density units, finite even where the piece's optical depth is not.
    const double u = p.cubic.invert_integral(std::max(0.0, tau - p.before) / scale_ / p.len);
    return p.ta + u * p.len;
}

}  // namespace vpm
