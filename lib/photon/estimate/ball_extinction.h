#pragma once
// Mean extinction over a kNN ball, for photons.extinction = "ball" (photon_map_integrator.h).
//
// The volume estimate S = sum f Phi / V(r) averages sigma_t L over the ball B(x, r); dividing it by
// the mean of sigma_t over the same ball makes the ratio consistent. Only the integral of sigma_t
// over the ball matters (V(r) cancels), so the quadrature follows where the medium is, per medium:
//
//   medium's box inside the ball       the medium's total mass integral sigma_t dV (computed once,
//                                      65536 Halton points over its box): exact up to that quadrature
//                                      however large the ball is (rule (b): k above the stored count
//                                      gives a ball around the whole map);
//   a closed form (Medium::ball_integral)  homogeneous: the ball inside the shape, a sphere's lens,
//                                      a box crossed through one axis's faces (caps); grid: the
//                                      ball inside one trilinear cell (mean = centre value). Exact,
//                                      one lookup (the quadrature cost 2.8-8.7x the rest
//                                      of the render in grids, the clipped one 4096 lookups);
//   ball inside the box, or a continuous medium (grid) crossing its box with r <= 1/4 of the box
//                                      the ball rule kBallRule over the whole ball (points outside
//                                      the box count 0, and there is no jump there to resolve);
//   a continuous medium crossing its box with a ball of at least two of its 16^3 mass cells
//                                      the mass lattice (photon/estimate/mass_lattice.h: cell masses cached
//                                      once, about 256 columns per ball, no lookups, far cheaper
//                                      than the clipped rule below; moments() too, from the cells'
//                                      first and second moments);
//   otherwise                          4096 Halton points over the part of the medium's box that the
//                                      ball's bounding cube covers, counting those inside the ball.
//
// A deterministic quadrature: it adds no noise of its own. Its error for the volume of a sphere in
// its box (an indicator, the hardest case): 256 points -3.0%, 1024 -1.3%, 4096 -0.2%, 65536 +0.07%.
// The second and third cases exist because a ball much larger than the medium would sample it with a
// few of its 32 points or none.
#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "core/math.h"
#include "scene/dielectric_regions.h"
#include "scene/media/medium.h"

namespace vpm {

// Quadratures of the mean of sigma_t over a ball lying inside the medium's box (bench_ball_extinction
// measures their error and cost; BallExtinction uses kBallRule):
//   halton32  32 Halton points through the volume-preserving warp (the rule before the mass lattice)
//   degree5   15 points, exact for polynomials up to degree 5 over the ball: the centre (weight
//             11/70), 6 on the axes at r sqrt(2/3) (9/140 each), 8 on the diagonals at
//             r (1/2, 1/2, 1/2) (2/35 each)
//   degree3   6 points on the axes at r sqrt(3/5) (1/6 each), exact up to degree 3
//   centre    sigma_t(x) alone ("point" inside the ball)
enum class BallRule { halton32, degree5, degree3, centre };
double ball_mean_by_rule(const Medium& m, const Vec3& x, double r, BallRule rule);

// The sigma_t-weighted moments of B(x, r): mass m0 = integral of sigma_t, the offset of its
// centroid from x and its covariance (photons.extinction = "linear", photon/estimate/linear_estimate.h).
struct BallMoments {
    double m0 = 0.0;
    Vec3 offset = Vec3::Zero();   // centroid - x
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();   // covariance about the centroid (sigma_t-weighted, normalised by m0)
};

struct LazyLattice;   // ball_extinction.cpp

// The region of a query among closed glass shapes (scene/dielectric_regions.h), in a scene with
// interior media (scene/interior_medium.h). The photons a region's map holds lit only the part of
// the ball in that region, so the extinction that normalises them is the integral over
// B(x, r) ∩ region: an interior medium counts in its own shape's region alone, clipped to the
// shape (exact when no other glass surface crosses the ball), and a medium that is everywhere
// counts by the share of the ball in the region (region_ball_fraction: exact where its sigma_t
// is the same on both sides of the interface, as VolumeEstimator divides without interior media).
struct BallRegion {
    const Surfaces* interfaces = nullptr;
    RegionMask region = 0;
};

class BallExtinction {
public:
    explicit BallExtinction(const std::vector<std::unique_ptr<Medium>>& media);
    // Copies share the mass lattices (built once, by whichever copy first needs one).
    // Mean over B(x, r) of the summed sigma_t of all media (overlapping media add). lookups: when
    // not null, the sigma_t evaluations made are added to it (the auto gather's cost count).
    // region: when not null, over B(x, r) ∩ region instead (BallRegion).
    double mean(const Vec3& x, double r, uint64_t* lookups = nullptr, const BallRegion* region = nullptr) const;
    // The integral of sigma_t over B(x, r) (over B(x, r) ∩ region when region is not null).
    double integral(const Vec3& x, double r, uint64_t* lookups = nullptr, const BallRegion* region = nullptr) const;
    // The integrals over B(x, ra) and B(x, rb), each what integral() gives, except that where both
    // need the clipped quadrature they share its points over the larger ball's cube (one pass).
    std::array<double, 2> integrals(const Vec3& x, double ra, double rb, uint64_t* lookups = nullptr,
                                    const BallRegion* region = nullptr) const;
    // Whether some medium is confined to a closed shape (Medium::interior_of()): then region
    // queries differ from plain ones.
    bool has_interior_media() const { return interior_media_; }
    // The moments above by the same quadratures (the lattice's for wide balls crossing a continuous
    // medium's box, as integral()); the ball's by the degree-5 rule in a
    // continuous medium, else by its 32 points and their antipodes (64; a homogeneous shape's jump
    // needs more than 15 points). Both symmetric: a ball of constant sigma_t has offset exactly 0.
    // lookups: as integral()'s, the sigma_t evaluations and lattice visits made (the plan's counted
    // work: the moments can be a third of a march's render in a thin grid).
    BallMoments moments(const Vec3& x, double r, uint64_t* lookups = nullptr, const BallRegion* region = nullptr) const;
    // The moments of B(x, ra) and B(x, rb), sharing the clipped quadrature's points as integrals().
    std::array<BallMoments, 2> moments(const Vec3& x, double ra, double rb, uint64_t* lookups = nullptr,
                                       const BallRegion* region = nullptr) const;

private:
    struct Entry {
        const Medium* medium;
        Bounds3 box;
        double mass;   // integral of sigma_t over the box
        Vec3 centroid = Vec3::Zero();   // of sigma_t over the box
        Eigen::Matrix3d second = Eigen::Matrix3d::Zero();   // integral of sigma_t (p - centroid)(p - centroid)^T over the box
        std::shared_ptr<LazyLattice> lattice;   // continuous media: built on the first wide crossing ball
        RegionMask shape = 0;   // the bit of the closed shape an interior medium is confined to; 0: everywhere
    };
    // Each entry's weight in a query of `region` over the balls of radii r[0..n): 0 for an interior
    // medium of another region, 1 for one of this region, the ball's share in the region for a
    // medium that is everywhere. Null: no region query (every weight 1).
    struct RegionWeights {
        bool on = false;
        double share[2] = {1.0, 1.0};
        RegionMask region = 0;
        double of(const Entry& e, int j) const { return e.shape ? ((region & e.shape) ? 1.0 : 0.0) : share[j]; }
    };
    RegionWeights region_weights(const Vec3& x, const double* r, int n, const BallRegion* region) const;
    void moments_n(const Vec3& x, const double* r, int n, BallMoments* out, uint64_t* lookups, const BallRegion* region) const;
    struct MomentSums;
    // Adds one entry's moments over B(x, r) to `sums` where a rule covers the ball; false where the
    // ball needs the clipped quadrature.
    bool entry_moments(const Entry& e, const Vec3& x, double r, MomentSums& sums, uint64_t* lookups) const;
    // The clipped quadrature for the radii marked `clipped`: one pass over the points of r_clip's cube.
    void clipped_moments(const Entry& e, const Vec3& x, const double* r, int n, const bool* clipped, double r_clip,
                         MomentSums* sums, uint64_t* lookups) const;
    void entry_integrals(const Entry& e, const Vec3& x, const double* r, double* out, int n, uint64_t* lookups) const;
    std::vector<Entry> entries_;
    bool interior_media_ = false;
};

}  // namespace vpm
