#pragma once
// photons.gather = "photon_beams": the beam x beam (1D) estimate of Jarosz, Nowrouzezahrai,
// Sadeghi & Jensen (TOG 2011) with widths from k nearest neighbours (docs/photon_beams.md).
// The photon paths' free flights in the media are stored as short beams (photon/map/photon_beam.h)
// in a BVH (photon/map/photon_beam_bvh.h). A camera segment o + t d, t in (0, t_end), collects
// every beam j it crosses within the width r and adds
//
//     Phi_j T(0, t_j) sigma_s(x_j) f(w_j . -d) K_1(u_j / r) / sin(theta_j),
//     K_1(u / r) = K(u / r) / (2 r n_1),   n_1 = int_0^1 K(t) dt (photon/estimate/kernels.h, dim 1),
//
// with x_j = o + t_j d the camera's point nearest to beam j, u_j the distance of the two lines
// there, theta_j their angle. sigma_s f is the media's sum at x_j (the 1D blur spreads the fluence
// of the beam, not the scattering), T(0, t_j) comes from one walk per camera segment
// (transport/transmittance_at_points.h: exact in homogeneous media, ratio tracking in grids).
//
// Widths (photons.beam_widths):
//   "balloon"       r = u of the k-th nearest beam of the segment; photons.estimator "classic"
//                   weighs the k nearest (E = k/(k-1) x truth for a uniform field of lines, constant
//                   kernel), "corrected" the k-1 nearer ones (unbiased for every normalised kernel).
//                   The width is bounded by photons.max_radius_mfp mean free paths of the densest
//                   medium the segment crosses (R = c / majorant), as the point gathers' balls are
//                   (photon/estimate/bounded_radius.h, the same split): N beams within R, N >= k
//                   the estimate, N = k - 1 zero (counted: band_zeros; that mass is in the first
//                   line's k-1 correction), N <= k - 2 no width (counted: starved) and the
//                   integrator gathers the segment as the collision gather does, the camera path
//                   going on from its free flight. For a Poisson field of lines the three sum to the
//                   truth exactly. Without the mfp bound, photons.max_radius bounds the width with a
//                   fixed-width estimate over the beams within it where fewer than k are.
//   "sample_point"  r_j = u of the k-th nearest other beam of beam j itself (its own segment as
//                   the query), bounded by photons.max_radius and by max_radius_mfp mean free paths
//                   at the beam's middle: independent of the camera ray, so unbiased for the blurred
//                   field for every k and kernel (no k-1 factor). A beam crossed by m < k others
//                   within its bound takes the bound (a fixed width); with no bound at all, u_m k / m,
//                   else (m = 0) the median width: every beam keeps its light (counted in the stats).
//   "density"       each piece of a beam gets a width from the beams' length per volume at its middle
//                   (photon/map/beam_density_widths.h): the u within which a segment of the beams'
//                   mean length crosses k beams, bounded as sample_point's. No k-nearest search: a
//                   camera segment weighs the pieces whose own-width cylinders it crosses. Unbiased
//                   for the blurred field as sample_point's (the widths do not depend on the ray).
//
// In a scene with closed glass shapes the beams are split by region (scene/dielectric_regions.h): a
// beam is one free flight, which crosses no glass, so it lies in one region. Each region's beams get
// their own BVH (and their own sample-point or density widths), and a camera segment in region R
// weighs only R's beams, as the point gathers' maps are split. A region with no beam is starved: the caller
// gathers its segments as the collision gather does.
#include <cstdint>
#include <string>
#include <vector>

#include <tbb/enumerable_thread_specific.h>

#include "core/math.h"
#include "core/sampling/rng.h"
#include "photon/estimate/kernels.h"
#include "photon/map/photon_beam.h"
#include "photon/map/photon_beam_bvh.h"
#include "render/photon_map/gathers/photon_beams_gather_stats.h"
#include "render/photon_map/gathers/region_parts.h"
#include "render/photon_map/gathers/segment_gather.h"
#include "scene/scene.h"

namespace vpm {

// density first: PhotonMapSettings::beam_widths{} (the default) is its value 0.
enum class BeamWidths { density, balloon, sample_point };
const char* beam_widths_name(BeamWidths w);
std::vector<std::string> beam_widths_names();   // photons.beam_widths' values

class PhotonBeamsGather : public SegmentGather {
public:
    // keep_kth: the classic numerator (the k-th beam weighed) rather than the corrected's (balloon
    // only). max_width: kInfinity for none.
    // max_width_mfp: photons.max_radius_mfp (0: off).
    // regions: the region of each beam (scene/dielectric_regions.h), or null (or empty) for one BVH.
    // width_scale in (0, 1] (photons.schedule = "progressive", photon/estimate/radius_schedule.h, d = 1):
    // balloon: the beams within s r_k of the k - 1 (classic: k) nearest, at width s r_k (exact on a
    // Poisson field of lines for every s <= 1, as the points' s r_k ball); sample_point: every width
    // times s (still the beam's own).
    PhotonBeamsGather(const Scene& scene, std::vector<PhotonBeam> beams, BeamWidths widths, size_t k, bool keep_kth,
                      const Kernel& kernel, double max_width, double max_width_mfp,
                      const std::vector<RegionMask>* regions = nullptr, double width_scale = 1.0);

    // Whether any beam is in a BVH.
    bool usable() const override;
    bool split_by_region() const override { return split_; }

    // The in-scattered radiance from the beams (of `region`, when split) along `ray` over (0, t_end);
    // dir unit length.
    Rgb in_scattering(const Ray& ray, double t_end, RegionMask region, Rng& rng,
                      bool* starved = nullptr) const override;
    void report_build(RunStats* stats, std::ostream* log) const override;
    void add_to(RunStats& run, std::ostream* log) const override;

    PhotonBeamsGatherStats stats() const;

private:
    struct Local {
        std::vector<BeamCrossing> hits;
        std::vector<double> widths, ts, transmittance;
        std::vector<uint32_t> order;
        uint64_t queries = 0, crossed = 0, tested = 0, starved = 0, band_zeros = 0, tracking_lookups = 0;
    };
    // One region's beams and their BVH (all beams where the scene has no glass shapes).
    struct Part {
        RegionMask region = 0;
        std::vector<PhotonBeam> beams;
        PhotonBeamBvh bvh;
    };
    const Scene& scene_;
    bool split_ = false;
    std::vector<Part> parts_;   // ascending region
    BeamWidths widths_;
    size_t k_;
    bool keep_kth_;
    Kernel kernel_;
    double max_width_;
    double max_width_mfp_;
    double width_scale_ = 1.0;
    std::vector<bool> exact_;
    PhotonBeamsGatherStats built_;
    mutable tbb::enumerable_thread_specific<Local> local_;

    Rgb scattering(const Vec3& x, double cos_theta) const;
    // beam_widths = "sample_point": each beam's width from its own k nearest other beams within its
    // bound (the widths' counts into built_); refuses a run where most widths would be guessed.
    std::vector<double> sample_point_widths(const std::vector<PhotonBeam>& beams, double max_width, double max_width_mfp);
    // beam_widths = "density": one width per beam from the beams' density, repeated for its pieces of `piece` length
    // (photon/map/beam_density_widths.h), bounded as sample_point's, times width_scale_.
    std::vector<double> density_widths(const std::vector<PhotonBeam>& beams, double piece);
    // The part's BVH (and sample-point widths), its counts into built_.
    void build_part(Part& part);
    // The part of `region` (the only one when not split); null where that region has no beam.
    const Part* part_of(RegionMask region) const;
    // The balloon width's bound for a segment: max_width_mfp over the largest majorant of the media
    // along it, at most max_width_ (max_width_ where the mfp bound is off or no medium is crossed).
    double segment_bound(const Ray& ray, double t_end) const;
};

}  // namespace vpm
