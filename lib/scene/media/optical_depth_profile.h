#pragma once
// The exact optical depth of one medium along a ray, as consecutive pieces on which the extinction
// is a cubic in the line parameter (a trilinear voxel cell, a uniform block, a homogeneous shape's
// chord). Built by Medium::optical_depth_profile; the march (transport/march_points.h) places its
// points by inverting it, so they follow the medium's own free-flight density and carry no
// majorant ratio (block-majorant points weighed up to 8e4 in smooth grids).
//
// Pieces are stored in density units with one sigma_t scale (as majorant_tracking.h's closed
// forms do), so a piece whose optical depth overflows still inverts to a finite t.
#include <cstddef>
#include <vector>

#include "scene/media/majorant_tracking.h"

namespace vpm {

class OpticalDepthProfile {
public:
    // Past this depth 1 - exp(-depth) rounds to 1 in double, and the march never asks beyond
    // -log(2^-53) < 37 (march_points.cpp): builders may stop adding pieces here.
    static constexpr double kEnoughDepth = 40.0;

    // Empties the profile; sigma_t = scale * density on every piece added next.
    void reset(double scale) {
        scale_ = scale;
        total_ = 0.0;
        pieces_.clear();
    }
    // Appends [ta, tb] (after every piece so far) with the density `cubic` in u = (t - ta) / (tb - ta).
    // Returns false once the total depth has reached kEnoughDepth (the builder may stop).
    // (Inline: it runs once per voxel cell of every camera segment the march gathers.)
    bool add(double ta, double tb, const tracking::CubicBernstein& cubic) {
        if (!(tb > ta)) return total_ < kEnoughDepth;
        const double depth = scale_ * (cubic.integral() * (tb - ta));
        if (depth > 0.0) {
            pieces_.push_back(Piece{ta, tb - ta, total_, depth, cubic});
            total_ += depth;
        }
        return total_ < kEnoughDepth;
    }
    // A piece of constant density.
    bool add_constant(double ta, double tb, double density) {
        return add(ta, tb, tracking::CubicBernstein{{density, density, density, density}});
    }

    // Appends the pieces of `other` shifted by `shift` in t (after every piece so far, so shift must
    // put them there). Returns false once the total depth has reached kEnoughDepth.
    bool append_shifted(const OpticalDepthProfile& other, double shift) {
        const double factor = other.scale_ / scale_;   // other's densities in this profile's scale
        for (const Piece& q : other.pieces_) {
            tracking::CubicBernstein cubic = q.cubic;
            for (double& c : cubic.c) c *= factor;
            pieces_.push_back(Piece{q.ta + shift, q.len, total_, q.depth, cubic});
            total_ += q.depth;
            if (!(total_ < kEnoughDepth)) return false;
        }
        return true;
    }
    double scale() const { return scale_; }

    // Optical depth over all pieces (may be cut at kEnoughDepth, or +inf on overflow).
    double total() const { return total_; }
    bool empty() const { return pieces_.empty(); }
    size_t size() const { return pieces_.size(); }

    // The t where the optical depth from the first piece's start reaches tau, for 0 <= tau < total().
    // `cursor` (start at 0) makes a sequence of increasing taus one pass over the pieces.
    double invert(double tau, size_t& cursor) const;

private:
    struct Piece {
        double ta, len;
        double before;   // optical depth of all earlier pieces
        double depth;    // this piece's optical depth (may be +inf)
        tracking::CubicBernstein cubic;   // density units
    };
    std::vector<Piece> pieces_;
    double scale_ = 1.0, total_ = 0.0;
};

}  // namespace vpm
