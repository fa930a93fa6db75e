#pragma once
// The photon map's camera path (integrator = "photon_map"). It is traced like the reference path
// tracer's until its first real collision in a medium (delta tracking: the collision estimator, so
// the line integral adds no bias of its own). There the volume estimate (volume_estimate.h) gives
// the in-scattered radiance and the path ends:
//
//     L += throughput * albedo(x) * S(x, w_o) / sigma_t
//
// With photons.direct = "nee" single scattering comes from next-event estimation and the map holds
// only photons that scattered before. The gather decides how a camera segment takes its estimate
// (gathers/gather_registry.h): at the collision, at march points along the segment, or from one
// BVH query of photon discs or beams. Where the map cannot answer (a starved map, a ball wider than
// photons.max_radius_mfp) the path continues like the path tracer's instead, which is unbiased.
// With a surface photon map the path ends at its first diffuse surface:
//
//     L += throughput * (direct by NEE + reflectance / pi * E(x))
//
// At its first photons.glass_splits glass hits a path from the camera follows both the reflection
// (weight F) and the refraction (weight 1 - F) instead of choosing one by F: a lamp seen in the glass
// is found by every sample, not by ~F of them. Each branch counts its own hits, so a path is a tree
// of at most 2^glass_splits leaves; paths continued from march points do not split. The roulette
// judges throughput over the product of the path's 1 / eta^2 factors, as the path tracer's does
// (transport/walk_steps.h).
//
// A CameraPath is a value over one pass's maps (PassMaps): it writes nothing but the counters it is
// handed, so a pilot traces candidate maps and gathers with counters of its own.
#include <cstdint>
#include <optional>

#include <tbb/enumerable_thread_specific.h>

#include "core/math.h"
#include "core/sampling/rng.h"
#include "photon/estimate/estimators.h"
#include "photon/map/photon_map.h"
#include "photon/map/region_photon_maps.h"
#include "render/photon_map/gathers/gather_registry.h"
#include "render/photon_map/photon_map_settings.h"
#include "render/photon_map/volume_estimate.h"
#include "scene/scene.h"
#include "transport/mis.h"
#include "transport/seen_through.h"

namespace vpm {

class SegmentGather;
class EquiangularSegment;
struct PathVertex;
struct SegmentPoint;

// One thread's counts and buffers of the camera paths, summed over threads for the run record and
// for the plan's counted cost.
struct CameraCounters {
    EstimateScratch scratch;
    EstimateCounts estimates;          // the volume map's queries (volume_estimate.h)
    EstimatorStats surface_stats;      // the surface map's
    uint64_t continued = 0;            // paths continued past a collision (a starved or too wide ball)
    uint64_t march_wide = 0;           // march points that took NEE and a continued path instead
    uint64_t rays = 0;                 // tracked segments: free flights, shadow rays, march transmittances
    uint64_t march_points = 0;
    double march_weight_max = 0.0, march_weight_sum = 0.0;   // march point weights relative to an exact majorant's
    uint64_t map_used = 0;             // estimates taken from a map, not continued past
    OpticalDepthProfile profile;       // transport/seen_through.h's buffer
};

// Every thread's counters.
using CounterSet = tbb::enumerable_thread_specific<CameraCounters>;

// Every thread's counts summed (maxima for the march weights), in the set's order.
struct CameraTotals {
    EstimateCounts estimates;
    EstimatorStats surface_stats;
    uint64_t continued = 0, march_wide = 0, rays = 0, march_points = 0, map_used = 0;
    double march_weight_max = 0.0, march_weight_sum = 0.0;
};
CameraTotals sum_counters(const CounterSet& counters);

// What a camera path reads of one pass: its maps, their rules and the gather in force.
struct PassMaps {
    VolumeEstimator volume;
    const PhotonMap* surface = nullptr;           // null: no surface map (paths bounce off surfaces)
    const Estimator* surface_estimator = nullptr;
    size_t k = 0;
    double max_radius = kInfinity;
    GatherMode gather = GatherMode::collision;    // never "auto" or "pilot": what they chose
    const SegmentGather* segment = nullptr;       // a segment gather in force (gathers/segment_gather.h): its pass's structure
    // Glass interfaces (scene/dielectric_regions.h): the maps split by region; the path tracks its
    // region and its estimates take that region's photons alone. Null: one region (the maps above).
    const RegionPhotonMaps* volume_regions = nullptr;
    const RegionPhotonMaps* surface_regions = nullptr;
};

class CameraPath {
public:
    // both_strategies: render.mis and a light a bounce can find (transport/single_scattering.h).
    CameraPath(const Scene& scene, const PhotonMapSettings& settings, const PassMaps& maps, bool both_strategies)
        : scene_(scene), settings_(settings), maps_(maps), both_strategies_(both_strategies) {}

    // The radiance along `ray` (towards -ray.dir) after `first_depth` scattering events; emission it
    // meets first counts as `first_emission` says.
    Rgb trace(const Ray& ray, int first_depth, Rng& rng, CameraCounters& c,
              const EmissionWeighting& first_emission = EmissionWeighting::camera()) const;

private:
    const Scene& scene_;
    const PhotonMapSettings& settings_;
    const PassMaps& maps_;
    bool both_strategies_;

    // What trace() carries from vertex to vertex.
    struct PathState {
        Ray ray;
        Rgb throughput;
        Rgb radiance;
        EmissionWeighting emission;
        RegionMask region;   // scene/dielectric_regions.h: toggled at every refraction through glass
        bool from_camera = true;    // not continued from a march point: it may march and split
        int splits_left = 0;        // glass hits at which this path still follows both events
        double radiance_scale = 1.0;   // the 1 / eta^2 factors of its refractions, for the roulette
    };
    enum class Step { end, next };
    // The walk from p's ray after `first_depth` scattering events to its end: the radiance it adds to p.
    void walk(PathState& p, int first_depth, Rng& rng, CameraCounters& c) const;
    // A mirror or glass hit: at glass with splits left the reflection is walked to its end here and p
    // goes on along the refraction; else one sampled event.
    Step specular_step(const SurfaceHit& hit, int depth, Rng& rng, CameraCounters& c, PathState& p) const;
    // A real collision in a medium: single scattering, then the map's estimate ends the path, or too
    // few photons and it scatters on. segment: the collision gather's equiangular segment, if any.
    Step collision_step(const MediumEvent& event, int depth, const EquiangularSegment* segment, Rng& rng,
                        CameraCounters& c, PathState& p) const;
    // A diffuse surface: the surface map's estimate ends the path, or it bounces on.
    Step diffuse_step(const SurfaceHit& hit, int depth, Rng& rng, CameraCounters& c, PathState& p) const;
    double surface_disc_share(const SurfaceHit& hit, double radius, RegionMask region) const;
    // The collision gather's equiangular segment over (0, t_end), its light added to p; none where it
    // finds no point or spot light.
    void equiangular_segment(double t_end, Rng& rng, CameraCounters& c, PathState& p,
                             std::optional<EquiangularSegment>& segment) const;
    // A march or beam segment that ends on a light or escapes: the light behind it and its gather.
    void light_behind_gathered_segment(const PathVertex& v, bool march, bool gathers, int depth, const Rgb* taken, Rng& rng,
                                       CameraCounters& c, PathState& p) const;
    // Single scattering at a medium vertex: `goes_on`, the path continues past x (MIS-weighted NEE
    // when render.mis); else the map ends it. `at`: x's segment also samples point and spot lights
    // equiangularly (transport/equiangular.h).
    Rgb single_scattering(const Vec3& x, const Vec3& dir, double g, bool goes_on, Rng& rng, CameraCounters& c,
                          const SegmentPoint* at = nullptr) const;
    // Whether the segment gathers by the march: gather "march", or "threshold" where the media's
    // majorant optical depth along it is at most photons.march_max_optical_depth.
    bool marches(const Ray& ray, double t_end) const;
    // The march: the in-scattered radiance along `ray` over (0, t_end) from stratified points, each
    // weighted by the other media's transmittance; optical_depth, when given, receives the segment's.
    // region: the segment's (scene/dielectric_regions.h).
    Rgb march_in_scattering(const Ray& ray, double t_end, int depth, RegionMask region, Rng& rng, CameraCounters& c,
                            double* optical_depth = nullptr) const;
    // The phase-weighted incident radiance at march point x (weight: the point's, for roulette).
    Rgb incident_at_march_point(const Vec3& x, const Vec3& dir, double g, double sigma_t, const Rgb& weight, int depth,
                                RegionMask region, Rng& rng, CameraCounters& c, const SegmentPoint* at = nullptr) const;
    // The volume estimate and the surface map of `region`'s photons (maps_'s own without regions).
    VolumeEstimator volume_in(RegionMask region) const;
    const PhotonMap* surface_in(RegionMask region) const;
    // The beam gathers' segment: one BVH query, single scattering by NEE when direct = "nee".
    // taken: the segment gather's value for this segment, taken in trace() (with the path's region).
    Rgb beam_in_scattering(const Ray& ray, double t_end, Rng& rng, CameraCounters& c, const Rgb& taken) const;
};

}  // namespace vpm
