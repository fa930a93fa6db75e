#pragma once
// A medium confined to the inside of a closed dielectric shape: `interior_medium = N` on a
// [[shapes]] table puts the N-th [[media]] table (0-based) inside that glass shape only, and
// nowhere else (smoke in a glass bottle; docs/config.md, docs/interior_medium.md).
//
// The medium's extinction is the inner medium's times the indicator of the shape's inside, so it
// is a Medium like any other: free flights, transmittance, majorants and optical depths run the
// inner medium over the ray's intervals inside the shape (a sphere's chord in closed form; a
// mesh's from the parity of its crossings along the ray). Every walk, camera path, shadow ray and
// gather that asks the scene's media sees the medium where it is, with no state along the path:
// the medium stack of a path is a function of where its segment lies, and each segment lies wholly
// inside or outside every closed shape. The inside is the shape's region bit
// (scene/dielectric_regions.h): a kNN ball's extinction counts the medium only for queries in that
// region (photon/estimate/ball_extinction.h).
#include <memory>
#include <string>

#include "scene/media/ball_clip_moments.h"
#include "scene/media/homogeneous_medium.h"
#include "scene/media/medium.h"
#include "scene/surfaces/surfaces.h"

namespace vpm {

class InteriorMedium final : public Medium {
public:
    // shape: the index among surfaces.dielectric_shapes(); `surfaces` outlives this medium.
    InteriorMedium(std::unique_ptr<Medium> inner, const Surfaces& surfaces, int shape);

    Bounds3 bounds() const override { return bounds_; }
    double sample_free_flight(const Ray& ray, double tmax, Rng& rng) const override;
    double transmittance(const Ray& ray, double tmax, Rng& rng) const override;
    double sigma_t(const Vec3& p) const override;
    // Closed forms: the inner medium's for a ball wholly inside a sphere shape, 0 for a ball wholly
    // outside the shape, and for a ball crossing the shape where a homogeneous inner medium is
    // uniform, sigma_t times the ball's part inside: a sphere's lens (scene/media/ball_clip_moments.h)
    // or a mesh's by the region points (shape_ball_moments); otherwise none (the caller integrates
    // sigma_t, which is clipped).
    bool ball_integral(const Vec3& x, double r, double& integral) const override;
    bool ball_moments(const Vec3& x, double r, double& m0, Vec3& m1, Eigen::Matrix3d& m2) const override;
    void majorant_pieces(const Ray& ray, double tmax, const MajorantVisitor& visit) const override;
    void optical_depth_profile(const Ray& ray, double tmax, OpticalDepthProfile& out) const override;
    int interior_of() const override { return shape_; }
    std::string describe() const override;

    const Medium& inner() const { return *inner_; }

    // The ray's parameter intervals inside the shape within [0, tmax], in order; returns their count
    // (at most kMaxIntervals; a mesh crossed more often along one ray than that is refused at a throw).
    static constexpr int kMaxIntervals = 32;
    int inside_intervals(const Ray& ray, double tmax, double (*t)[2]) const;
    bool contains(const Vec3& p) const;

private:
    // Where a ball lies against the shape: wholly inside, wholly outside, or crossing its surface.
    enum class BallSide { inside, outside, crossing };
    BallSide ball_side(const Vec3& x, double r) const;
    // A ball crossing the shape inside a homogeneous inner medium's uniform part: its sigma_t and
    // the moments of the ball's part inside the shape (about x).
    bool uniform_lens(const Vec3& x, double r, double& sigma, ClipMoments& lens) const;

    std::unique_ptr<Medium> inner_;
    const HomogeneousMedium* homogeneous_;   // inner_ when it is homogeneous, else null
    const Surfaces& surfaces_;
    DielectricShape shape_geometry_;
    int shape_;
    Bounds3 bounds_;
};

}  // namespace vpm
