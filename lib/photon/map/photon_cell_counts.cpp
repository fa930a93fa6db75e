#include "photon/map/photon_cell_counts.h"

#include <algorithm>
#include <cmath>

#include <tbb/parallel_sort.h>

#include "core/morton.h"

namespace vpm {

PhotonCellCounts::PhotonCellCounts(const PhotonMap& map) {
    if (map.empty()) return;
    const Bounds3 b = map.bounds();
    lo_ = b.lo;
    extent_ = (b.hi - b.lo).cwiseMax(Vec3::Constant(1e-300));
    diagonal_ = extent_.norm() / kMortonScale;
    codes_.resize(map.size());
    for (size_t i = 0; i < map.size(); ++i) codes_[i] = morton_code(map.position(i), lo_, extent_);
    tbb::parallel_sort(codes_.begin(), codes_.end());
}

bool PhotonCellCounts::surely_holds(const Vec3& x, double r, size_t k) const {
    if (codes_.size() < k || !(r > 0.0)) return false;
    // Outside the box the clamped code names a cell x is not in.
    for (int a = 0; a < 3; ++a)
        if (!(x[a] >= lo_[a] && x[a] <= lo_[a] + extent_[a])) return false;
    // A cell of 2^b steps per axis has diagonal 2^b diagonal_; the largest b with that <= r (a
    // margin of 1e-9 for the rounding of decoded positions), at most the whole box.
    const double steps = r * (1.0 - 1e-9) / diagonal_;
    if (!(steps >= 1.0)) return false;
    const int b = std::min(kMortonBits, int(std::floor(std::log2(steps))));
    const int shift = 3 * b;
    const uint64_t cell = b >= kMortonBits ? 0 : morton_code(x, lo_, extent_) >> shift;
    const uint64_t first = b >= kMortonBits ? 0 : cell << shift;
    const uint64_t end = b >= kMortonBits ? ~uint64_t(0) : (cell + 1) << shift;
    const auto from = std::lower_bound(codes_.begin(), codes_.end(), first);
    if (size_t(codes_.end() - from) < k) return false;
    // k photons from `from` on all in the cell: the (k-1)-th after it is still below its end.
    return *(from + std::ptrdiff_t(k - 1)) < end || (b >= kMortonBits);
}

}  // namespace vpm
