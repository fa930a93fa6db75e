#pragma once
// A bounding-volume hierarchy over photon beams (photon/map/photon_beam.h) for the photon-beams
// gather (render/photon_map/gathers/photon_beams_gather.h). A camera segment o + t d, t in [0, tmax], and a
// beam b + v w, v in [0, length], cross where their lines come closest: at t*, v* with the
// distance u between the lines there and the angle theta between d and w
// (photon_beam_crossing). A beam counts for a segment only where t* and v* both lie inside.
//
// Two queries, each exact (the same beams as a loop over all of them with photon_beam_crossing,
// tests/photon/map/photon_beam_bvh_test.cpp):
//   for_each_crossed  every beam with u below its own width r_j (the sample-point form: the boxes
//                     are the beams' segments swept by r_j);
//   nearest           the k beams of smallest u (ties by index) below a bound (the balloon form:
//                     built with widths 0, the bound shrinks as the k nearest so far come in).
// Nodes are boxes around the swept segments, split at the median of the longest axis of the
// segments' midpoints; leaves hold up to 4 items (beams, or pieces of long beams: max_piece below).
// Build and queries are deterministic.
#include <cstdint>
#include <vector>

#include "core/math.h"
#include "photon/map/photon_beam.h"

namespace vpm {

struct BeamCrossing {
    uint32_t index = 0;   // the beam's index in the build's input
    double t = 0.0;       // along the camera segment
    double v = 0.0;       // along the beam
    double u = 0.0;       // distance between the lines at (t, v)
    double sin_theta = 0.0;
};

// Lines closer to parallel than this (sin theta) never cross: the 1D kernel's 1/sin(theta) has no
// finite limit there, and such a pair has measure zero in any field of directions.
constexpr double kMinBeamSin = 1e-7;

// Whether the segment [0, tmax] of (o, d) and the beam (origin, w, length) cross, filling c
// (c.index is left alone). d and w unit length.
inline bool photon_beam_crossing(const Vec3& o, const Vec3& d, double tmax, const Vec3& origin, const Vec3& w,
                                 double length, BeamCrossing& c) {
    const Vec3 n = d.cross(w);
    const double s2 = n.squaredNorm();
    if (!(s2 > kMinBeamSin * kMinBeamSin)) return false;
    const Vec3 e = o - origin;
    const double a = d.dot(w), de = d.dot(e), we = w.dot(e);
    const double t = (a * we - de) / s2;
    if (!(t >= 0.0 && t <= tmax)) return false;
    const double v = we + a * t;
    if (!(v >= 0.0 && v <= length)) return false;
    const double sin_theta = std::sqrt(s2);
    c.t = t;
    c.v = v;
    c.u = std::abs(e.dot(n)) / sin_theta;
    c.sin_theta = sin_theta;
    return true;
}

class PhotonBeamBvh {
public:
    PhotonBeamBvh() = default;
    // radii: one width per beam (the sample-point form), or empty for widths 0 (the balloon form).
    // Beams of non-finite or non-positive length, or non-finite width, are left out.
    // max_piece: a beam longer than this is stored as pieces of equal length at most max_piece,
    // each its own item with its own box (0 or kInfinity: whole beams). A long diagonal beam's box
    // is mostly empty space; its pieces' boxes hug it. A crossing has one foot v on the beam, so it
    // is found in exactly one piece (pieces own [v0, v1), the last [v0, length]) and every query's
    // answer is the same for any max_piece.
    // per_piece: radii holds one width per piece instead, in the order of the beams and, within a
    // beam, of v (pieces(beam, max_piece) of each); a piece of no positive finite width is left out.
    PhotonBeamBvh(const std::vector<PhotonBeam>& beams, const std::vector<double>& radii, double max_piece = 0.0,
                  bool per_piece = false);

    // The pieces the BVH cuts a beam into for max_piece (0 for a beam it leaves out: non-finite or
    // no length), and piece p's extent [v0, v1] along it.
    static uint32_t pieces(const PhotonBeam& b, double max_piece);
    static double piece_start(const PhotonBeam& b, uint32_t p, uint32_t m) { return p == 0 ? 0.0 : b.length * double(p) / double(m); }
    static double piece_end(const PhotonBeam& b, uint32_t p, uint32_t m) { return p + 1 == m ? b.length : b.length * double(p + 1) / double(m); }

    // The piece length the gather uses: 4 / sqrt(lambda), lambda the beams' total length over the
    // volume of their bounding box (1 / sqrt(lambda) is the spacing of a field of lines of that
    // density), kept within [mean length / 8, mean length] so that a flat or degenerate field
    // neither explodes nor stays whole; 0 for no beams. From counts and geometry only. The factor 4:
    // in bench/bench_photon_beam_bvh.cpp's furnace field the k-nearest query costs within ~10% of
    // the best factor measured (2) at half its memory (docs/photon_beams.md, "Cost").
    static double automatic_piece_length(const std::vector<PhotonBeam>& beams);
    // The automatic piece is at least the beams' mean length over this, so the pieces number at
    // most (this + 1) per beam on average (ceil adds at most one to each beam's share).
    static constexpr double kPiecesPerMeanLength = 8.0;
    // Bytes of an index over beams cut by automatic_piece_length, at most, per beam: its items and
    // nodes (at most one node per item) for kPiecesPerMeanLength + 1 pieces each.
    static double max_bytes_per_beam() { return (kPiecesPerMeanLength + 1.0) * double(sizeof(Item) + sizeof(Node)); }

    // visit(const BeamCrossing&, double width) for every beam that crosses the segment with u below
    // its width. `dir` unit length; tmax finite or kInfinity. tested (if given) += crossing tests made.
    template <class Visit>
    void for_each_crossed(const Vec3& origin, const Vec3& dir, double tmax, Visit&& visit, uint64_t* tested = nullptr) const;

    // The k crossing beams of smallest u, u < max_distance (kInfinity: unbounded), in `out`
    // sorted by (u, index); fewer where fewer cross. `skip`: a beam index left out (a beam's own
    // neighbours; UINT32_MAX for none). Best-first: nodes in the order of a lower bound of their
    // distance to the segment (the larger of the max-norm and the line bound, photon/map/segment_box_distance.h;
    // boxes outside the segment's slab skipped), stopping at the first node farther than the k-th
    // crossing found so far, so no node beyond the final k-th distance is opened.
    void nearest(const Vec3& origin, const Vec3& dir, double tmax, size_t k, double max_distance,
                 std::vector<BeamCrossing>& out, uint32_t skip = UINT32_MAX, uint64_t* tested = nullptr) const;

    size_t size() const { return beam_count_; }         // beams stored
    size_t item_count() const { return items_.size(); }   // pieces stored
    size_t node_count() const { return nodes_.size(); }
    size_t memory_bytes() const { return items_.capacity() * sizeof(Item) + nodes_.capacity() * sizeof(Node); }

private:
    struct Item {
        Vec3 origin, dir;   // the whole beam's line (the crossing is computed on it)
        double length, width;
        double v0, v1;      // this piece: v in [v0, v1), the last piece v in [v0, length]
        uint32_t index;
    };
    struct Node {
        Bounds3 bounds;
        uint32_t first;   // leaf: first item; inner: index of the second child (the first follows)
        uint32_t count;   // leaf: number of items; inner: 0
    };
    uint32_t build(uint32_t begin, uint32_t end);
    // The crossing of the segment with item `it`'s beam, if its foot lies on this piece.
    static bool crosses(const Vec3& o, const Vec3& d, double tmax, const Item& it, BeamCrossing& c) {
        if (!photon_beam_crossing(o, d, tmax, it.origin, it.dir, it.length, c)) return false;
        if (!(c.v >= it.v0 && (c.v < it.v1 || it.v1 == it.length))) return false;
        c.index = it.index;
        return true;
    }
    size_t beam_count_ = 0;
    std::vector<Item> items_;
    std::vector<Node> nodes_;
};

template <class Visit>
void PhotonBeamBvh::for_each_crossed(const Vec3& origin, const Vec3& dir, double tmax, Visit&& visit, uint64_t* tested) const {
    if (nodes_.empty() || !(tmax >= 0.0)) return;
    const Ray ray{origin, dir};
    uint32_t stack[64];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
        const Node& node = nodes_[stack[--top]];
        double t0, t1;
        // A crossing's camera point lies within the width of a point of the beam, so inside the box.
        if (!node.bounds.intersect(ray, tmax, t0, t1)) continue;
        if (node.count == 0) {
            stack[top++] = node.first;
            stack[top++] = uint32_t(&node - nodes_.data()) + 1;
            continue;
        }
        if (tested) *tested += node.count;
        for (uint32_t i = node.first; i < node.first + node.count; ++i) {
            const Item& b = items_[i];
            BeamCrossing c;
            if (!crosses(origin, dir, tmax, b, c) || !(c.u < b.width)) continue;
            visit(c, b.width);
        }
    }
}

}  // namespace vpm
