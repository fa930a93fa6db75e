#pragma once
// The photon map's estimate at a point x in a medium, the subject of the project, in one place:
//
//   1. the map holds fewer than k photons: no ball anywhere, the camera path continues;
//   2. the radius bound (photons.max_radius_mfp mean free paths, photon/estimate/bounded_radius.h):
//      decided on the run's decision map when there is one (then the estimate's ball is unbounded),
//      else on the estimate's own list;
//   3. the kNN estimate S of sigma_t times the phase-weighted incident radiance (photon/estimate/
//      estimators.h: the estimator, its kernel and rules), over the k nearest photons or, with
//      photons.neighbours = "walks", the k nearest walks (photon/estimate/walk_estimate.h);
//   4. the extinction normalisation (photons.extinction): S over sigma_t at x ("point"), over the
//      mean sigma_t of the ball ("ball"), or photon weights exact for a radiance linear across the
//      ball ("linear"); with photons.clustering = "leave_group_out" each half of the walk groups
//      counted within the other half's ball (photon/estimate/group_estimate.h).
//
// Collisions and march points call estimate() alike; the rule says whether the value is used, the
// estimate is 0 (exactly k - 1 photons within the bound: the k-1 correction counts that mass), or
// the path must continue because the map cannot answer within the bound.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/math.h"
#include "photon/estimate/ball_extinction.h"
#include "photon/estimate/bounded_radius.h"
#include "photon/estimate/estimators.h"
#include "photon/map/photon_cell_counts.h"
#include "photon/map/photon_map.h"
#include "render/photon_map/photon_map_settings.h"
#include "scene/dielectric_regions.h"

namespace vpm {

// The map photons.max_radius_mfp's switch is decided on, apart from the estimate's own map.
struct DecisionMap {
    const PhotonMap* map = nullptr;             // null: decide on the estimate's own list
    const PhotonCellCounts* cells = nullptr;    // answers most decisions in thin media without a query
    double ratio = 1.0;                         // emitted photons of the estimate's map per one of this map's
};

// Per-thread buffers of estimate() (no allocation once grown).
struct EstimateScratch {
    GatherBuffers buffers;
    std::vector<Rgb> linear_weights;   // photons.extinction = "linear"
};

// Per-thread counts of estimate() (the pilot's cost model reads queries, decisions and lookups).
struct EstimateCounts {
    EstimatorStats stats;           // kNN queries of the volume map by case
    uint64_t decisions = 0;         // kNN queries of the decision map (decisions its cell counts did not settle)
    uint64_t lookups = 0;           // sigma_t lookups of the ball quadrature
    uint64_t linear_fallbacks = 0;  // linear sums that went negative: the ball normalisation instead
    void merge(const EstimateCounts& o);
};

struct VolumeEstimate {
    BoundedQuery rule = BoundedQuery::use_estimate;
    Rgb incident = Rgb::Zero();   // phase-weighted incident radiance at x, when rule is use_estimate
};

// A pass's volume map with the rules its estimates follow. A view: every reference outlives it.
struct VolumeEstimator {
    const PhotonMap& map;
    DecisionMap decision;
    size_t k;
    const Estimator& estimator;     // the pass's, with its radius scale (photons.schedule)
    double max_radius;              // kInfinity for none
    double max_radius_mfp;          // 0: no bound
    ExtinctionNormalisation extinction;
    bool leave_group_out;           // PhotonMapSettings::leaves_group_out()
    const BallExtinction& ball;
    Neighbourhood neighbourhood = Neighbourhood::photons;   // photons.neighbours
    // Glass interfaces (scene/dielectric_regions.h): `map` holds the photons of `region` alone, and
    // the estimate is divided by the share of its ball inside the region (docs/interface_regions.md).
    // Null: no interfaces.
    const Surfaces* interfaces = nullptr;
    RegionMask region = 0;

    // Whether the map is too small for any estimate: every query continues the path.
    bool starved() const { return map.size() < k; }
    // The estimate at x (sigma_t: the total extinction there; w_o: towards the camera; g: the phase's).
    VolumeEstimate estimate(const Vec3& x, const Vec3& w_o, double g, double sigma_t, EstimateScratch& scratch,
                            EstimateCounts& counts) const;

private:
    // The decision map's photons and radius equivalent to "k photons of the map within `radius`".
    struct DecisionBall {
        size_t k = 0;
        double radius = 0;
    };
    DecisionBall decision_ball(double radius) const;
    // The kNN list to gather: k, or more for the leave-group-out halves.
    size_t gather_count() const;
    // Whether the ball's extinction is over its part in x's region (scene with interior media,
    // photon/estimate/ball_extinction.h: BallRegion), and whether the estimate s used it.
    bool region_extinction() const;
    bool uses_ball_extinction(const Estimate<Rgb>& s) const;
    // Step 4: S normalised by the extinction (s over the ball of radius `bound` for leave-group-out).
    Rgb normalised(const Estimate<Rgb>& s, const Vec3& x, const Vec3& w_o, double g, double bound, double sigma_t,
                   EstimateScratch& scratch, EstimateCounts& counts) const;
};

}  // namespace vpm
