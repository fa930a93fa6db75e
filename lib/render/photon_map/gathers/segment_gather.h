#pragma once
// A gather that answers a whole camera segment with one query of a structure built per pass
// ("point_beam": a BVH of photon discs; "photon_beams": a BVH of the photons' free flights). The
// point gathers ("collision", "march", "threshold") need none: they estimate at points of the
// segment (render/photon_map/volume_estimate.h), which the camera path does itself.
//
// A new segment gather is its file pair here (a class deriving from SegmentGather and a build
// function), one line in gather_registry.cpp, a row in docs/config.md and a test.
#include <iosfwd>
#include <memory>
#include <vector>

#include "core/math.h"
#include "core/sampling/rng.h"
#include "photon/map/photon_beam.h"
#include "photon/map/photon_map.h"
#include "photon/map/region_photon_maps.h"
#include "scene/dielectric_regions.h"

namespace vpm {

class Scene;
struct PhotonMapSettings;
struct RunStats;

// What a segment gather is built from, once per pass.
struct SegmentGatherInputs {
    const Scene& scene;
    const PhotonMapSettings& settings;
    const PhotonMap& volume;             // the pass's volume map
    std::vector<PhotonBeam>& beams;      // the pass's photon beams (gathers that store them take them)
    size_t k;                            // the pass's k (photons.schedule)
    double max_radius;                   // kInfinity for none
    double disc_scale;                   // the pass's disc radius scale (photons.schedule), in (0, 1]
    // A scene with closed glass shapes (scene/dielectric_regions.h): the volume map split by region
    // and the region of each beam; the gather then builds one structure per region. Null: one region.
    const RegionPhotonMaps* volume_regions = nullptr;
    const std::vector<RegionMask>* beam_regions = nullptr;
};

class SegmentGather {
public:
    virtual ~SegmentGather() = default;
    // Whether the pass gave it anything to query; if not, the pass's segments gather like "march".
    virtual bool usable() const = 0;
    // The in-scattered radiance from the pass's photons along `ray` over (0, t_end) (t_end may be
    // kInfinity; ray.dir unit length), single scattering excluded. `region` is the camera path's
    // region along the segment (a segment crosses no glass): a gather split by region reads only the
    // photons or beams of that region. *starved (when given) is set when the gather has no estimate
    // for this segment (balloon photon beams crossed by fewer than k beams, a region with no discs or
    // beams): the value is then 0 and not an estimate, and the caller gathers the segment otherwise
    // (camera_path.cpp: as the collision gather does).
    virtual Rgb in_scattering(const Ray& ray, double t_end, RegionMask region, Rng& rng,
                              bool* starved = nullptr) const = 0;
    // Whether the structure is split by region, so that the camera path must track its region.
    virtual bool split_by_region() const = 0;
    // The build's phases (stats, when given) and its log line with any warning (log, when given).
    virtual void report_build(RunStats* stats, std::ostream* log) const = 0;
    // Adds this pass's build figures and query counts to the run's section for this gather; with a
    // log, writes the run's totals (once, when the run's statistics are collected).
    virtual void add_to(RunStats& run, std::ostream* log) const = 0;
};

using SegmentGatherBuild = std::unique_ptr<SegmentGather> (*)(SegmentGatherInputs& inputs);

}  // namespace vpm
