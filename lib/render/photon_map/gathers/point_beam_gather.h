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
// replaced by sigma_s f at the foot point y_i over the kernel-weighted mean sigma_t of the disc the
// estimate blurs over: centre y_i, radius r_i, perpendicular to the segment (a fixed quadrature of
// kDiscPoints points). The expected sum over photons of K(delta_i / r_i) sigma_t(y_i + delta_i) is
// that mean times the fluence, so this is exact for a smooth fluence in a medium with a jump: the
// albedo inside, 0 where the foot is outside, above 1 where the disc reaches out (a ball around the
// photon would boost photons under a face the segment crosses head on, whose discs do not reach
// out). r_i is the distance to the beam_k-th nearest *other* photon
// (photon/map/photon_radii.h), bounded by photons.max_radius and by max_radius_mfp mean free
// paths at x_i; both bounds depend on the photon alone, so the estimate stays a sample-point
// estimate, unbiased on a uniform density for every k (docs/beam_estimate.md). T(0, t_i) comes
// from one walk along each medium's majorant pieces per query: the optical depth itself in
// homogeneous media, ratio tracking in grids, whose running product over the tentative collisions
// before t is an unbiased estimate of T(0, t) for every t at once (the photons' order by (t, index)
// fixes the random stream, so a seed gives the same image on any thread count).
//
// In a scene with closed glass shapes the discs are split by region (scene/dielectric_regions.h),
// as the point gathers' maps are: each region's radii and BVH come from that region's photons
// alone, and a camera segment in region R crosses only R's discs. A region with no disc (fewer than
// beam_k + 1 photons) is starved: the caller gathers its segments as the collision gather does.
#include <cstdint>
#include <vector>

#include <tbb/enumerable_thread_specific.h>

#include "core/math.h"
#include "core/sampling/rng.h"
#include "photon/estimate/kernels.h"
#include "photon/map/photon_disc_bvh.h"
#include "photon/map/photon_map.h"
#include "photon/map/region_photon_maps.h"
#include "render/photon_map/gathers/point_beam_gather_stats.h"
#include "render/photon_map/gathers/region_parts.h"
#include "render/photon_map/gathers/segment_gather.h"
#include "scene/scene.h"

namespace vpm {

class PointBeamGather : public SegmentGather {
public:
    // Builds the radii (parallel) and the BVH over `map`, which must outlive this object.
    // max_radius: kInfinity for none; max_radius_mfp: 0 for none. radius_scale in (0, 1]: every disc's
    // radius times it after the bounds (photons.schedule = "progressive", photon/estimate/radius_schedule.h;
    // still the photon's own, so the estimate stays a sample-point one, unbiased on a uniform density).
    // regions: the same photons split by region (their maps must outlive this object too), or null
    // for one structure over `map`.
    PointBeamGather(const Scene& scene, const PhotonMap& map, size_t k, const Kernel& kernel, double max_radius,
                    double max_radius_mfp, double radius_scale = 1.0, const RegionPhotonMaps* regions = nullptr);

    // Whether any photon has a disc: a map of at most k photons has no k-th other photon.
    bool usable() const override;
    bool split_by_region() const override { return split_; }

    // The in-scattered radiance from the map (of `region`, when split) along `ray` over (0, t_end)
    // (t_end may be kInfinity). `dir` of the ray is unit length.
    Rgb in_scattering(const Ray& ray, double t_end, RegionMask region, Rng& rng,
                      bool* starved = nullptr) const override;
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
    // One region's photons and their discs (the whole map where the scene has no glass shapes).
    struct Part {
        RegionMask region = 0;
        const PhotonMap* map = nullptr;
        PhotonDiscBvh bvh;
    };
    const Scene& scene_;
    const PhotonMap& map_;
    Kernel kernel_;
    bool split_ = false;
    std::vector<Part> parts_;   // ascending region
    PointBeamGatherStats built_;
    std::vector<bool> exact_;   // per medium: homogeneous, so its majorant pieces are sigma_t exactly
    bool foot_point_ = false;   // some medium has a jump (homogeneous shapes): the foot-point rule
    std::vector<Vec3> disc_points_;   // then: the unit disc's quadrature (x, y, kernel weight), weights summing to 1
    mutable tbb::enumerable_thread_specific<Local> local_;

    // Each photon's radius (beam_k-th nearest other photon of its map, bounded) and the BVH of discs.
    void build_part(Part& part, size_t k, double max_radius, double max_radius_mfp, double radius_scale);
    // The part of `region` (the only one when not split); null where that region has no photon.
    const Part* part_of(RegionMask region) const;
    // sigma_s f at the foot point x: the sum over the media of sigma_t,m albedo_m f_m.
    Rgb scattering(const Vec3& x, double cos_theta) const;
    // The kernel-weighted mean of the media's sigma_t over the disc of radius r around y, normal dir.
    double disc_sigma_t(const Vec3& y, const Vec3& dir, double r) const;
    // sigma_s f / sigma_t at the photon's position x (continuous media: the plain estimate).
    Rgb albedo_phase(const Vec3& x, double cos_theta) const;
    // T(0, t_i) for the hits sorted by t, every medium in one pass along its majorant pieces: the
    // optical depth in homogeneous media, ratio tracking (one walk for all t_i) in the others.
    void transmittances(const Ray& ray, const std::vector<Hit>& hits, std::vector<double>& out, Rng& rng, Local& local) const;
};

}  // namespace vpm
