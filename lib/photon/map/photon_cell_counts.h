#pragma once
// How many of a photon map's photons lie in the cells of an octree over its bounds, read from the
// photons' sorted Morton codes (core/morton.h: a cell is a range of codes, two binary searches): a
// certificate that a ball holds at least k photons without a kNN query. The cell that contains x
// at the finest level whose cells fit in B(x, r) (diagonal <= r) lies inside the ball, so if it
// holds k photons the ball does too. "Not known" otherwise: the caller then queries.
//
// The radius bound's decision map asks "k photons within r?" at every bounded query
// (render/photon_map/photon_map_integrator.h); in thin media, where the answer is always yes and the ball
// holds thousands of photons, the certificate answers it from one cell (the kNN queries had cost
// the thin cube's march 68% more time per pass: docs/studies/heldout_scenes.md section 31). The answer is the
// query's, so the image does not change.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/math.h"
#include "photon/map/photon_map.h"

namespace vpm {

class PhotonCellCounts {
public:
    PhotonCellCounts() = default;
    explicit PhotonCellCounts(const PhotonMap& map);

    // True: B(x, r) surely holds at least k of the map's photons (distance <= r, as PhotonMap::knn
    // counts them). False: not known from the cells.
    bool surely_holds(const Vec3& x, double r, size_t k) const;

private:
    Vec3 lo_ = Vec3::Zero(), extent_ = Vec3::Ones();
    double diagonal_ = 0.0;          // of the whole box, in steps of kMortonScale
    std::vector<uint64_t> codes_;    // the photons' codes, sorted
};

}  // namespace vpm
