#pragma once
// photons.gather = "point_beam": the beam radiance estimate (Jarosz, Zwicker & Jensen 2008) in the
// photon-map renderer. Each camera segment through the media is answered by one query: every
// photon i whose disc (radius r_i, perpendicular to the segment) the segment crosses at foot point
// t_i contributes
//
//     T(0, t_i) * [sigma_s f / sigma_t](x_i) * Phi_i * K(delta_i / r_i) / (n_2 pi r_i^2)
//
// Photons are stored at real collisions, so their density estimates sigma_t times the phase-
// weighted fluence, and the segment integral of T sigma_s (f L) takes the albedo (the mixture of
// the media at x_i) and no division by sigma_t. Where a medium has a jump (homogeneous shapes:
// Medium::continuous() false) a disc would blur the boundary by its radius, so there the albedo is
// replaced by sigma_s f at the foot point y_i over the mean sigma_t of photon i's ball (the point
// gathers' "ball" extinction, per photon): 1 inside, 0 where the disc reaches out of the media,
// above 1 for a photon whose ball sticks out; inside a homogeneous medium it is the albedo exactly,
// so the uniform analysis holds there. r_i is the distance to the beam_k-th nearest *other* photon
// (photon/map/photon_radii.h), bounded by photons.max_radius and by max_radius_mfp mean free
// paths at x_i; both bounds depend on the photon alone, so the estimate stays a sample-point
// estimate, unbiased on a uniform density for every k (docs/beam_estimate.md). T(0, t_i) comes
// from one walk along each medium's majorant pieces per query: the optical depth itself in
// homogeneous media, ratio tracking in grids, whose running product over the tentative collisions
// before t is an unbiased estimate of T(0, t) for every t at once (the photons' order by (t, index)
// fixes the random stream, so a seed gives the same image on any thread count).
#include <cstdint>
#include <vector>

#include <tbb/enumerable_thread_specific.h>

#include "core/math.h"
#include "core/sampling/rng.h"
#include "photon/estimate/kernels.h"
#include "photon/map/photon_disc_bvh.h"
#include "photon/map/photon_map.h"
#include "render/photon_map/gathers/point_beam_gather_stats.h"
#include "render/photon_map/gathers/segment_gather.h"
#include "scene/scene.h"

namespace vpm {

class PointBeamGather : public SegmentGather {
public:
    // Builds the radii (parallel) and the BVH over `map`, which must outlive this object.
    // max_radius: kInfinity for none; max_radius_mfp: 0 for none. radius_scale in (0, 1]: every disc's
    // radius times it after the bounds (photons.schedule = "progressive", photon/estimate/radius_schedule.h;
    // still the photon's own, so the estimate stays a sample-point one, unbiased on a uniform density).
    PointBeamGather(const Scene& scene, const PhotonMap& map, size_t k, const Kernel& kernel, double max_radius,
               double max_radius_mfp, double radius_scale = 1.0);

    // Whether any photon has a disc: a map of at most k photons has no k-th other photon.
    bool usable() const override { return bvh_.size() > 0; }

    // The in-scattered radiance from the map along `ray` over (0, t_end) (t_end may be kInfinity).
    // `dir` of the ray is unit length.
    Rgb in_scattering(const Ray& ray, double t_end, Rng& rng, bool* starved = nullptr) const override;
    void report_build(RunStats* stats, std::ostream* log) const override;
    void add_to(RunStats& run, std::ostream* log) const override;

    // Counts so far (queries over all threads) plus the build figures.
    PointBeamGatherStats stats() const;

private:
    struct Hit {
        double t;
        double d2;
        double r;
        uint32_t index;
    };
    struct Local {
        std::vector<Hit> hits;
        std::vector<double> transmittance;   // T(0, t) of each hit
        uint64_t queries = 0, crossed = 0, tracking_lookups = 0;
    };
    const Scene& scene_;
    const PhotonMap& map_;
    Kernel kernel_;
    PhotonDiscBvh bvh_;
    PointBeamGatherStats built_;
    std::vector<bool> exact_;   // per medium: homogeneous, so its majorant pieces are sigma_t exactly
    bool foot_point_ = false;   // some medium has a jump (homogeneous shapes): the foot-point rule
    std::vector<float> inv_ball_sigma_t_;   // then per stored photon: 1 / mean sigma_t over its ball (0: no disc)
    mutable tbb::enumerable_thread_specific<Local> local_;

    // sigma_s f at the foot point x: the sum over the media of sigma_t,m albedo_m f_m.
    Rgb scattering(const Vec3& x, double cos_theta) const;
    // sigma_s f / sigma_t at the photon's position x (continuous media: the plain estimate).
    Rgb albedo_phase(const Vec3& x, double cos_theta) const;
    // T(0, t_i) for the hits sorted by t, every medium in one pass along its majorant pieces: the
    // optical depth in homogeneous media, ratio tracking (one walk for all t_i) in the others.
    void transmittances(const Ray& ray, const std::vector<Hit>& hits, std::vector<double>& out, Rng& rng, Local& local) const;
};

}  // namespace vpm
