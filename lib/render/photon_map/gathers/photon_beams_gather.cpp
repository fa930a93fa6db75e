#include "render/photon_map/gathers/photon_beams_gather.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <sstream>
#include <ostream>

#include <tbb/parallel_for.h>

#include "core/error.h"
#include "core/henyey_greenstein.h"
#include "core/progress.h"
#include "photon/estimate/bounded_radius.h"
#include "photon/map/beam_density_widths.h"
#include "render/photon_map/photon_map_settings.h"
#include "render/run/run_record.h"
#include "render/run/run_stats.h"
#include "transport/transmittance_at_points.h"

namespace vpm {

const char* beam_widths_name(BeamWidths w) {
    switch (w) {
        case BeamWidths::balloon: return "balloon";
        case BeamWidths::sample_point: return "sample_point";
        case BeamWidths::density: return "density";
    }
    return "balloon";
}

std::vector<std::string> beam_widths_names() {
    std::vector<std::string> names;
    for (BeamWidths w : {BeamWidths::balloon, BeamWidths::sample_point, BeamWidths::density}) names.push_back(beam_widths_name(w));
    return names;
}

PhotonBeamsGather::PhotonBeamsGather(const Scene& scene, std::vector<PhotonBeam> beams, BeamWidths widths, size_t k,
                                     bool keep_kth, const Kernel& kernel, double max_width, double max_width_mfp,
                                     const std::vector<RegionMask>* regions, double width_scale)
    : scene_(scene), split_(regions != nullptr && !regions->empty()), widths_(widths), k_(k), keep_kth_(keep_kth),
      kernel_(kernel), max_width_(max_width), max_width_mfp_(max_width_mfp), width_scale_(width_scale),
      exact_(homogeneous_media(scene)) {
    built_.widths = beam_widths_name(widths);
    built_.k = k;
    if (split_) {
        if (regions->size() != beams.size())
            throw Error("photon beams: " + std::to_string(regions->size()) + " regions for " +
                        std::to_string(beams.size()) + " beams");
        std::map<RegionMask, std::vector<PhotonBeam>> split;   // beams keep their order within a region
        for (size_t j = 0; j < beams.size(); ++j) split[(*regions)[j]].push_back(beams[j]);
        std::vector<PhotonBeam>().swap(beams);
        for (auto& [region, list] : split) {
            parts_.emplace_back();
            parts_.back().region = region;
            parts_.back().beams = std::move(list);
        }
    } else {
        parts_.resize(1);
        parts_[0].beams = std::move(beams);
    }
    for (Part& part : parts_) build_part(part);
    built_.regions = parts_.size();
    built_.bytes_per_beam = double(built_.bvh_bytes) / double(std::max<uint64_t>(built_.recorded, 1));
    // Guessed widths (no bound) blur a beam's light as far as the guess goes, so a run where most
    // widths would be guessed is refused (docs/photon_beams.md).
    const uint64_t guessed = built_.widths_extrapolated + built_.widths_typical;
    if (2 * guessed > built_.recorded)
        throw Error("photons.beam_widths = \"sample_point\": " + std::to_string(guessed) + " of the " +
                    std::to_string(built_.recorded) +
                    " photon beams are crossed by fewer than photons.k = " + std::to_string(k_) +
                    " others within their own segments and no bound is set, so most widths would be guessed; "
                    "set photons.max_radius_mfp > 0 (mean free paths; default 2) or photons.max_radius > 0, a "
                    "smaller photons.k, more photons, or photons.beam_widths = \"balloon\"");
}

void PhotonBeamsGather::build_part(Part& part) {
    // Long beams as pieces in the camera rays' BVH (photon/map/photon_beam_bvh.h): the same answers,
    // fewer tests. The sample-point widths' queries (each beam's own segment) keep whole beams: where
    // most own segments are crossed by fewer than k beams (dense media) a query searches every item
    // within its bound, and pieces multiply the items (docs/photon_beams.md, "Cost").
    const double piece = PhotonBeamBvh::automatic_piece_length(part.beams);
    built_.piece_length = std::max(built_.piece_length, piece);
    std::vector<double> radii;
    if (widths_ == BeamWidths::sample_point) {
        radii = sample_point_widths(part.beams, max_width_, max_width_mfp_);
        if (width_scale_ < 1.0)
            for (double& r : radii) r *= width_scale_;
    } else if (widths_ == BeamWidths::density) {
        radii = density_widths(part.beams, piece);
    }
    const Timer bvh_timer;
    part.bvh = PhotonBeamBvh(part.beams, radii, piece, widths_ == BeamWidths::density);
    built_.bvh_seconds += bvh_timer.seconds();
    built_.recorded += part.beams.size();
    built_.beams += part.bvh.size();
    built_.beams_left_out += part.beams.size() - part.bvh.size();   // non-finite or empty flights: no width, no light
    built_.pieces += part.bvh.item_count();
    built_.bvh_bytes += part.bvh.memory_bytes() + part.beams.capacity() * sizeof(PhotonBeam);
}

bool PhotonBeamsGather::usable() const { return any_part_built(parts_); }

const PhotonBeamsGather::Part* PhotonBeamsGather::part_of(RegionMask region) const { return part_of_region(parts_, split_, region); }

std::vector<double> PhotonBeamsGather::sample_point_widths(const std::vector<PhotonBeam>& beams, double max_width,
                                                           double max_width_mfp) {
    // Each beam's width from its own k nearest other beams (its segment as the query), found in
    // a BVH of widths 0 within the beam's bound; independent of any camera ray, so any width kept
    // here leaves the estimate unbiased for the blurred field, and every beam gets one (none is
    // left out).
    const Timer timer;
    const PhotonBeamBvh plain(beams, {});
    std::vector<double> radii(beams.size(), kInfinity);
    std::vector<uint32_t> found(beams.size(), 0);
    std::vector<double> bounds(beams.size(), max_width);
    tbb::enumerable_thread_specific<std::vector<BeamCrossing>> scratch;
    tbb::enumerable_thread_specific<uint64_t> tested(0);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, beams.size(), 256), [&](const tbb::blocked_range<size_t>& range) {
        std::vector<BeamCrossing>& near = scratch.local();
        uint64_t& tests = tested.local();
        for (size_t j = range.begin(); j != range.end(); ++j) {
            const PhotonBeam& b = beams[j];
            // max_radius_mfp mean free paths at the beam's middle (as the point gathers' balls).
            double sigma_t = 0.0;
            for (const auto& m : scene_.media) sigma_t += m->sigma_t(b.origin + 0.5 * b.length * b.dir);
            const double bound = bounded_radius(max_width, max_width_mfp, sigma_t);
            bounds[j] = bound;
            plain.nearest(b.origin, b.dir, b.length, k_, bound, near, uint32_t(j), &tests);
            found[j] = uint32_t(near.size());
            // Fewer than k within a bound: the bound itself (a fixed width). Without one, the m < k
            // found extrapolated: crossings within u grow as u (a field of lines), so the k-th
            // would lie near u_m k / m.
            if (near.size() == k_) radii[j] = near.back().u;
            else if (std::isfinite(bound)) radii[j] = bound;
            else if (!near.empty()) radii[j] = near.back().u * double(k_) / double(near.size());
        }
    });
    // A beam no other one crosses and with no bound: the median of the widths measured with all k
    // neighbours (or, where no beam has k, of the extrapolated ones); with no crossing at all
    // there is no width to take, and the run is refused.
    std::vector<double> measured;
    for (size_t j = 0; j < beams.size(); ++j)
        if (found[j] == k_ && std::isfinite(radii[j]) && radii[j] > 0.0) measured.push_back(radii[j]);
    if (measured.empty())
        for (double r : radii)
            if (std::isfinite(r) && r > 0.0) measured.push_back(r);
    double typical = kInfinity;
    if (!measured.empty()) {
        std::nth_element(measured.begin(), measured.begin() + std::ptrdiff_t(measured.size() / 2), measured.end());
        typical = measured[measured.size() / 2];
    }
    for (size_t j = 0; j < beams.size(); ++j) {
        if (found[j] == k_) continue;
        if (std::isfinite(bounds[j])) {
            ++built_.widths_bounded;
        } else if (found[j] > 0) {
            ++built_.widths_extrapolated;
        } else {
            ++built_.widths_typical;
            radii[j] = typical;
        }
    }
    for (uint64_t t : tested) built_.widths_tested += t;
    built_.widths_seconds += timer.seconds();
    return radii;
}

Rgb PhotonBeamsGather::scattering(const Vec3& x, double cos_theta) const {
    Rgb sum = Rgb::Zero();
    for (const auto& m : scene_.media) {
        const double s = m->sigma_t(x);
        if (s > 0.0) sum += s * m->albedo() * hg_eval(cos_theta, m->g());
    }
    return sum;
}

double PhotonBeamsGather::segment_bound(const Ray& ray, double t_end) const {
    if (!(max_width_mfp_ > 0.0)) return max_width_;
    double majorant = 0.0;
    for (const auto& m : scene_.media)
        m->majorant_pieces(ray, t_end, [&](double, double, double sigma) {
            majorant = std::max(majorant, sigma);
            return true;
        });
    return bounded_radius(max_width_, max_width_mfp_, majorant);
}

std::vector<double> PhotonBeamsGather::density_widths(const std::vector<PhotonBeam>& beams, double piece) {
    const Timer timer;
    auto bound = [&](const Vec3& x) {
        double sigma_t = 0.0;
        for (const auto& m : scene_.media) sigma_t += m->sigma_t(x);
        return bounded_radius(max_width_, max_width_mfp_, sigma_t);
    };
    BeamDensityWidths w = beam_density_widths(beams, piece, k_, bound, width_scale_);
    built_.widths_seconds += timer.seconds();
    built_.widths_tested += w.queries * kBeamDensityNeighbours;
    built_.widths_bounded += w.bounded;
    return std::move(w.widths);
}

Rgb PhotonBeamsGather::in_scattering(const Ray& ray, double t_end, RegionMask region, Rng& rng, bool* starved) const {
    if (starved) *starved = false;
    Local& local = local_.local();
    const Part* part = part_of(region);
    if (part == nullptr || part->bvh.size() == 0) {   // a region no beam reached: no estimate here
        ++local.queries;
        ++local.starved;
        if (starved) *starved = true;
        return Rgb::Zero();
    }
    std::vector<BeamCrossing>& hits = local.hits;
    std::vector<double>& widths = local.widths;
    hits.clear();
    widths.clear();
    ++local.queries;
    if (widths_ == BeamWidths::balloon) {
        const double bound = segment_bound(ray, t_end);
        part->bvh.nearest(ray.origin, ray.dir, t_end, k_, bound, hits, UINT32_MAX, &local.tested);
        double r;
        if (hits.size() == k_) {
            r = hits.back().u;
            if (!keep_kth_) hits.pop_back();   // corrected: the k-th beam sets the width only
        } else if (bound == max_width_ && std::isfinite(max_width_)) {
            r = max_width_;   // the fixed bound: a fixed-width estimate over every beam within it
        } else if (hits.size() + 1 == k_) {
            // k - 1 within the mfp bound (or in all): 0, the mass the corrected estimate's k - 1
            // already holds (photon/estimate/bounded_radius.h).
            ++local.band_zeros;
            return Rgb::Zero();
        } else {   // no width: the caller gathers this segment otherwise (it is not 0)
            ++local.starved;
            if (starved) *starved = true;
            return Rgb::Zero();
        }
        // A progressive pass weighs the beams within s r (the kernel is 0 beyond its width).
        widths.assign(hits.size(), width_scale_ < 1.0 ? r * width_scale_ : r);
    } else {
        part->bvh.for_each_crossed(ray.origin, ray.dir, t_end, [&](const BeamCrossing& c, double width) {
            hits.push_back(c);
            widths.push_back(width);
        }, &local.tested);
    }
    local.crossed += hits.size();
    if (hits.empty()) return Rgb::Zero();
    // In order along the ray, ties by index: one transmittance walk serves every beam, and the
    // random stream is consumed in an order that does not depend on the BVH's traversal.
    const size_t n = hits.size();
    local.order.resize(n);
    std::iota(local.order.begin(), local.order.end(), 0u);
    std::sort(local.order.begin(), local.order.end(), [&](uint32_t a, uint32_t b) {
        return hits[a].t < hits[b].t || (hits[a].t == hits[b].t && hits[a].index < hits[b].index);
    });
    local.ts.resize(n);
    local.transmittance.resize(n);
    for (size_t i = 0; i < n; ++i) local.ts[i] = hits[local.order[i]].t;
    transmittance_at_points(scene_, exact_, ray, local.ts.data(), n, local.transmittance.data(), rng, local.tracking_lookups);
    Rgb sum = Rgb::Zero();
    for (size_t i = 0; i < n; ++i) {
        const BeamCrossing& h = hits[local.order[i]];
        const double r = widths[local.order[i]];
        if (h.u > r) continue;   // beyond a progressive pass's s r_k (the kernels' profiles do not stop at 1)
        const double w = local.transmittance[i] * kernel_.weight(h.u * h.u / (r * r), 1) / (2.0 * r * h.sin_theta);
        if (w == 0.0) continue;
        const PhotonBeam& b = part->beams[h.index];
        const Rgb f = scattering(ray.at(h.t), b.dir.dot(-ray.dir));
        if ((f == 0.0).all()) continue;
        sum += w * b.power * f;
    }
    return sum;
}

PhotonBeamsGatherStats PhotonBeamsGather::stats() const {
    PhotonBeamsGatherStats s = built_;
    for (const Local& l : local_) {
        s.queries += l.queries;
        s.crossed += l.crossed;
        s.tested += l.tested;
        s.starved += l.starved;
        s.band_zeros += l.band_zeros;
        s.tracking_lookups += l.tracking_lookups;
    }
    return s;
}

void PhotonBeamsGather::report_build(RunStats* stats, std::ostream* log) const {
    const PhotonBeamsGatherStats b = this->stats();
    if (stats) {
        if (widths_ != BeamWidths::balloon) stats->phase("build_beam_widths", b.widths_seconds);
        stats->phase("build_photon_beam_bvh", b.bvh_seconds);
    }
    if (!log) return;
    const std::string estimator = std::string(keep_kth_ ? "classic" : "corrected") +
                                  (kernel_.is_constant() ? "" : "/" + kernel_.label());
    *log << "photon_beams: " << b.beams << " beams";
    if (split_) *log << " in " << b.regions << " regions (glass interfaces: a segment weighs its own region's)";
    *log << ", widths \"" << b.widths << "\" (k = " << b.k << ", " << estimator
         << " in 1D)";
    if (widths_ != BeamWidths::balloon) *log << ", widths " << b.widths_seconds << " s";
    *log << ", BVH " << b.bvh_seconds << " s, " << b.bytes_per_beam << " bytes/beam\n";
    // No beam at all (no media, or every flight outside them): the segments gather like "march".
    if (!usable() && scene_.has_media())
        *log << "warning: no photon beam was recorded in the media, so this pass gathers like \"march\"\n";
}

void PhotonBeamsGather::add_to(RunStats& run, std::ostream* log) const {
    PhotonBeamsGatherStats total = stats();   // this pass's sizes, the run's times and counts
    if (const PhotonBeamsGatherStats* before = run.sections.find<PhotonBeamsGatherStats>()) total.add_run_totals(*before);
    run.sections.get<PhotonBeamsGatherStats>() = total;
    if (log) {
        const double q = total.queries ? double(total.queries) : 1.0;
        *log << "photon_beams: " << total.queries << " segment queries weighed " << total.crossed << " beams ("
             << (total.queries ? double(total.crossed) / q : 0.0) << " per query, "
             << (total.queries ? double(total.tested) / q : 0.0) << " crossing tests per query); " << total.starved
             << " found fewer than k - 1 beams within the width's bound (the path went on there, as the collision gather's), "
             << total.band_zeros << " exactly k - 1 (0, the corrected estimate's k - 1 split)\n";
    }
    if (const uint64_t guessed = total.widths_extrapolated + total.widths_typical) {
        std::ostringstream w;
        w << "photons.beam_widths = \"sample_point\": " << guessed << " of " << total.recorded
          << " beams are crossed by fewer than photons.k others and no bound is set; their widths are extrapolated ("
          << total.widths_extrapolated << ") or the median (" << total.widths_typical
          << "), and such wide beams blur their light beyond the medium's features; photons.max_radius_mfp or "
             "photons.max_radius bound them";
        if (std::find(run.warnings.begin(), run.warnings.end(), w.str()) == run.warnings.end()) run.warn(w.str(), log);
    }
    if (widths_ == BeamWidths::sample_point && 2 * total.widths_bounded > total.recorded) {
        std::ostringstream w;
        w << "photons.beam_widths = \"sample_point\": " << total.widths_bounded << " of " << total.recorded
          << " beams are crossed by fewer than photons.k others within their bound (photons.max_radius_mfp mean free "
             "paths, or photons.max_radius), so they take the bound as a fixed width: a blur of the bound's size, "
             "unbiased only as it shrinks (a dense cube read -4% at 2 mean free paths); a smaller "
             "photons.max_radius_mfp, more photons, or beam_widths = \"balloon\" (which continues the camera path "
             "there) reduce it";
        if (std::find(run.warnings.begin(), run.warnings.end(), w.str()) == run.warnings.end()) run.warn(w.str(), log);
    }
    // Sample-point widths have no starved segment: where few beams cross a camera segment the
    // estimate is mostly 0 with rare large values: unbiased over maps, but one image reads low
    // (docs/photon_beams.md), so the run says so.
    if (widths_ == BeamWidths::sample_point && total.queries > 0 && total.crossed < total.queries) {
        const std::string prefix = "photons.beam_widths = \"sample_point\": the camera segments crossed ";
        // One warning with the run's totals: the earlier passes' is replaced.
        run.warnings.erase(std::remove_if(run.warnings.begin(), run.warnings.end(),
                                          [&](const std::string& w) { return w.rfind(prefix, 0) == 0; }),
                           run.warnings.end());
        std::ostringstream w;
        w.precision(3);
        w << prefix << double(total.crossed) / double(total.queries)
          << " beams each on average (fewer than 1), so the beams' light comes from rare segments and one image most "
             "likely reads low; more photons or beam_widths = \"balloon\" (which continues the camera path where few "
             "beams are) give a usable image";
        run.warn(w.str(), log);
    }
}

std::unique_ptr<SegmentGather> build_photon_beams_gather(SegmentGatherInputs& in) {
    auto gather = std::make_unique<PhotonBeamsGather>(in.scene, std::move(in.beams), in.settings.beam_widths, in.k,
                                                      in.settings.estimator.traits().keeps_kth, in.settings.estimator.kernel(),
                                                      in.max_radius, in.settings.max_radius_mfp, in.beam_regions,
                                                      in.disc_scale);
    in.beams.clear();
    return gather;
}

void PhotonBeamsGatherStats::add_run_totals(const PhotonBeamsGatherStats& earlier) {
    widths_seconds += earlier.widths_seconds;
    widths_tested += earlier.widths_tested;
    bvh_seconds += earlier.bvh_seconds;
    queries += earlier.queries;
    crossed += earlier.crossed;
    tested += earlier.tested;
    starved += earlier.starved;
    band_zeros += earlier.band_zeros;
    tracking_lookups += earlier.tracking_lookups;
}

void PhotonBeamsGatherStats::write(RunRecord& record) const {
    record.set("photons.photon_beams.widths", widths);
    record.set("photons.photon_beams.k", k);
    record.set("photons.photon_beams.recorded", recorded);
    record.set("photons.photon_beams.beams", beams);
    record.set("photons.photon_beams.regions", regions);
    record.set("photons.photon_beams.pieces", pieces);
    record.set("photons.photon_beams.piece_length", piece_length);
    record.set("photons.photon_beams.bvh_bytes", bvh_bytes);
    record.set("photons.photon_beams.bytes_per_beam", bytes_per_beam);
    record.set("photons.photon_beams.widths_seconds", widths_seconds);
    record.set("photons.photon_beams.widths_tested", widths_tested);
    record.set("photons.photon_beams.bvh_seconds", bvh_seconds);
    record.set("photons.photon_beams.queries", queries);
    record.set("photons.photon_beams.crossed", crossed);
    record.set("photons.photon_beams.tested", tested);
    record.set("photons.photon_beams.starved", starved);
    record.set("photons.photon_beams.band_zeros", band_zeros);
    record.set("photons.photon_beams.widths_bounded", widths_bounded);
    record.set("photons.photon_beams.widths_extrapolated", widths_extrapolated);
    record.set("photons.photon_beams.widths_typical", widths_typical);
    record.set("photons.photon_beams.beams_left_out", beams_left_out);
    record.set("photons.photon_beams.tracking_lookups", tracking_lookups);
}

}  // namespace vpm
