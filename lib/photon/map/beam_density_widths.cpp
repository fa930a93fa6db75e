#include "photon/map/beam_density_widths.h"

#include <algorithm>
#include <cmath>

#include <nanoflann.hpp>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "photon/map/photon_beam_bvh.h"

namespace vpm {

namespace {

// The pieces' middles and lengths, in PhotonBeamBvh's per-piece order.
struct PieceCloud {
    std::vector<Vec3> middle;
    std::vector<double> length;
    size_t kdtree_get_point_count() const { return middle.size(); }
    double kdtree_get_pt(uint32_t i, size_t d) const { return middle[i][int(d)]; }
    template <class BBox>
    bool kdtree_get_bbox(BBox&) const { return false; }
};

using Tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, PieceCloud, double, uint32_t>,
                                                 PieceCloud, 3, uint32_t>;

PieceCloud piece_cloud(const std::vector<PhotonBeam>& beams, double max_piece) {
    PieceCloud c;
    for (const PhotonBeam& b : beams) {
        const uint32_t m = PhotonBeamBvh::pieces(b, max_piece);
        for (uint32_t p = 0; p < m; ++p) {
            const double v0 = PhotonBeamBvh::piece_start(b, p, m), v1 = PhotonBeamBvh::piece_end(b, p, m);
            c.middle.push_back(b.origin + 0.5 * (v0 + v1) * b.dir);
            c.length.push_back(v1 - v0);
        }
    }
    return c;
}

// Beam length per unit volume over the pieces' bounding box: where a piece has too few neighbours
// for its own estimate (0 for a flat or single-point set).
double mean_density(const PieceCloud& c) {
    Bounds3 box;
    double total = 0.0;
    for (size_t i = 0; i < c.middle.size(); ++i) {
        box.extend(c.middle[i]);
        total += c.length[i];
    }
    const Vec3 e = box.hi - box.lo;
    const double volume = e.x() * e.y() * e.z();
    return volume > 0.0 ? total / volume : 0.0;
}

// lambda at x: the nearest pieces' lengths (all but the farthest found) over the ball of the farthest.
double local_density(const Tree& tree, const PieceCloud& cloud, const Vec3& x, std::vector<uint32_t>& index,
                     std::vector<double>& d2, double fallback) {
    nanoflann::KNNResultSet<double, uint32_t> result(index.size());
    result.init(index.data(), d2.data());
    tree.findNeighbors(result, x.data(), nanoflann::SearchParams());
    const size_t found = result.size();
    if (found < 2 || !(d2[found - 1] > 0.0)) return fallback;
    double length = 0.0;
    for (size_t j = 0; j + 1 < found; ++j) length += cloud.length[index[j]];
    const double r = std::sqrt(d2[found - 1]);
    return length / (4.0 / 3.0 * kPi * r * r * r);
}

}  // namespace

BeamDensityWidths beam_density_widths(const std::vector<PhotonBeam>& beams, double max_piece, size_t k,
                                      const std::function<double(const Vec3&)>& bound, double scale) {
    BeamDensityWidths out;
    const PieceCloud cloud = piece_cloud(beams, max_piece);
    const size_t n = cloud.middle.size();
    out.widths.assign(n, 0.0);
    if (n == 0) return out;
    double total = 0.0;
    size_t counted = 0;
    for (const PhotonBeam& b : beams)
        if (PhotonBeamBvh::pieces(b, max_piece) > 0) total += b.length, ++counted;
    const double mean_length = total / double(counted);
    const double fallback_density = mean_density(cloud);
    Tree tree(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(10));
    tree.buildIndex();
    const size_t neighbours = std::min(kBeamDensityNeighbours, n);
    // Each beam's first piece in the per-piece order.
    std::vector<size_t> first(beams.size() + 1, 0);
    for (size_t j = 0; j < beams.size(); ++j) first[j + 1] = first[j] + PhotonBeamBvh::pieces(beams[j], max_piece);
    tbb::enumerable_thread_specific<uint64_t> bounded(0);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, beams.size(), 256), [&](const tbb::blocked_range<size_t>& range) {
        std::vector<uint32_t> index(neighbours);
        std::vector<double> d2(neighbours);
        for (size_t j = range.begin(); j != range.end(); ++j) {
            if (first[j + 1] == first[j]) continue;
            const Vec3 x = beams[j].origin + 0.5 * beams[j].length * beams[j].dir;
            const double lambda = local_density(tree, cloud, x, index, d2, fallback_density);
            const double estimate = lambda > 0.0 ? 2.0 * double(k) / (kPi * lambda * mean_length) : kInfinity;
            const double cap = bound(x);
            double w = estimate;
            if (!(estimate <= cap)) {
                w = std::isfinite(cap) ? cap : mean_length;   // no density and no bound: the mean length
                ++bounded.local();
            }
            for (size_t i = first[j]; i < first[j + 1]; ++i) out.widths[i] = w * scale;
        }
    });
    out.queries = counted;
    for (uint64_t b : bounded) out.bounded += b;
    return out;
}

}  // namespace vpm
