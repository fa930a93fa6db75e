#include "render/photon_map/gathers/point_beam_gather.h"

#include <algorithm>
#include <cmath>
#include <ostream>

#include <tbb/parallel_for.h>

#include "core/henyey_greenstein.h"
#include "core/progress.h"
#include "photon/map/photon_radii.h"
#include "render/photon_map/photon_map_settings.h"
#include "render/run/run_record.h"
#include "render/run/run_stats.h"
#include "scene/media/homogeneous_medium.h"

namespace vpm {

PointBeamGather::PointBeamGather(const Scene& scene, const PhotonMap& map, size_t k, const Kernel& kernel, double max_radius,
                                 double max_radius_mfp, double radius_scale, const RegionPhotonMaps* regions)
    : scene_(scene), map_(map), kernel_(kernel), split_(regions != nullptr && !regions->empty()) {
    for (const auto& m : scene.media) exact_.push_back(dynamic_cast<const HomogeneousMedium*>(m.get()) != nullptr);
    // Only media with a jump need the disc's mean sigma_t; where every medium is continuous the plain
    // estimate is kept. The quadrature: a sunflower of points, even in area, weighed by the kernel.
    for (const auto& m : scene.media) foot_point_ = foot_point_ || !m->continuous();
    if (foot_point_) {
        constexpr int kDiscPoints = 64;
        const double golden = kPi * (3.0 - std::sqrt(5.0));
        double total = 0.0;
        for (int j = 0; j < kDiscPoints; ++j) {
            const double s2 = (double(j) + 0.5) / double(kDiscPoints);   // squared radius, even in area
            const double s = std::sqrt(s2), phi = golden * double(j);
            const double w = kernel_.weight(s2, 2);
            if (w > 0.0) disc_points_.emplace_back(s * std::cos(phi), s * std::sin(phi), w);
            total += w;
        }
        for (Vec3& q : disc_points_) q.z() /= total;
    }
    if (split_) {
        parts_.resize(regions->regions());
        for (size_t i = 0; i < parts_.size(); ++i) {
            parts_[i].region = regions->region(i);
            parts_[i].map = &regions->map(i);
        }
    } else {
        parts_.resize(1);
        parts_[0].map = &map;
    }
    for (Part& part : parts_) build_part(part, k, max_radius, max_radius_mfp, radius_scale);
    built_.k = k;
    built_.regions = parts_.size();
    const double n = double(std::max<size_t>(map.size(), 1));
    built_.bvh_bytes_per_photon = double(built_.bvh_bytes) / n;
    built_.map_bytes_per_photon = double(map.memory_bytes()) / n;
    built_.total_bytes_per_photon = built_.bvh_bytes_per_photon + built_.map_bytes_per_photon;
}

void PointBeamGather::build_part(Part& part, size_t k, double max_radius, double max_radius_mfp, double radius_scale) {
    const PhotonMap& map = *part.map;
    const Timer radii_timer;
    std::vector<double> radii = photon_radii(map, k);
    std::vector<Vec3> centres(map.size());
    for (size_t i = 0; i < map.size(); ++i) {
        centres[i] = map.position(i);
        double r = std::min(radii[i], max_radius);
        if (max_radius_mfp > 0.0 && std::isfinite(r)) {
            // The collision gather's bound (photon/estimate/bounded_radius.h), per photon: it depends on x_i
            // only, so the radius stays independent of the query.
            double sigma_t = 0.0;
            for (const auto& m : scene_.media) sigma_t += m->sigma_t(centres[i]);
            if (sigma_t > 0.0) r = std::min(r, max_radius_mfp / sigma_t);
        }
        radii[i] = radius_scale < 1.0 ? r * radius_scale : r;
    }
    built_.radii_seconds += radii_timer.seconds();
    const Timer bvh_timer;
    part.bvh = PhotonDiscBvh(centres, radii);
    built_.bvh_seconds += bvh_timer.seconds();
    built_.photons += part.bvh.size();
    built_.bvh_bytes += part.bvh.memory_bytes();
}

bool PointBeamGather::usable() const { return any_part_built(parts_); }

const PointBeamGather::Part* PointBeamGather::part_of(RegionMask region) const { return part_of_region(parts_, split_, region); }

Rgb PointBeamGather::scattering(const Vec3& x, double cos_theta) const {
    Rgb sum = Rgb::Zero();
    for (const auto& m : scene_.media) {
        const double s = m->sigma_t(x);
        if (s > 0.0) sum += s * m->albedo() * hg_eval(cos_theta, m->g());
    }
    return sum;
}

double PointBeamGather::disc_sigma_t(const Vec3& y, const Vec3& dir, double r) const {
    const Frame frame(dir);
    double mean = 0.0;
    for (const Vec3& q : disc_points_) {
        const Vec3 x = y + r * (q.x() * frame.s + q.y() * frame.t);
        for (const auto& m : scene_.media) mean += q.z() * m->sigma_t(x);
    }
    if (mean > 0.0) return mean;
    for (const auto& m : scene_.media) mean += m->sigma_t(y);   // a disc whose points all miss: the foot's
    return mean;
}

Rgb PointBeamGather::albedo_phase(const Vec3& x, double cos_theta) const {
    if (scene_.media.size() == 1) return scene_.media.front()->albedo() * hg_eval(cos_theta, scene_.media.front()->g());
    Rgb sum = Rgb::Zero();
    double sigma_t = 0.0;
    for (const auto& m : scene_.media) {
        const double s = m->sigma_t(x);
        sum += s * m->albedo() * hg_eval(cos_theta, m->g());
        sigma_t += s;
    }
    if (sigma_t > 0.0) return sum / sigma_t;
    // A stored position rounded just outside every medium: the media's mean.
    for (const auto& m : scene_.media) sum += m->albedo() * hg_eval(cos_theta, m->g());
    return sum / double(scene_.media.size());
}

void PointBeamGather::transmittances(const Ray& ray, const std::vector<Hit>& hits, std::vector<double>& out, Rng& rng,
                                Local& local) const {
    const size_t n = hits.size();
    out.assign(n, 1.0);
    const double t_last = hits.back().t;
    for (size_t mi = 0; mi < scene_.media.size(); ++mi) {
        const Medium& m = *scene_.media[mi];
        const bool exact = exact_[mi];
        size_t i = 0;
        double acc = exact ? 0.0 : 1.0;   // optical depth so far (exact) or the ratio-tracking product
        m.majorant_pieces(ray, t_last, [&](double ta, double tb, double mu) {
            if (exact) {   // the majorant is sigma_t itself
                const double before = std::exp(-acc);
                for (; i < n && hits[i].t <= ta; ++i) out[i] *= before;
                for (; i < n && hits[i].t <= tb; ++i) out[i] *= std::exp(-(acc + mu * (hits[i].t - ta)));
                acc += mu * (tb - ta);
                return true;
            }
            // Ratio tracking: tentative collisions at rate mu, each scaling the product by
            // 1 - sigma_t / mu. The product over those before t is unbiased for T(0, t) at every t.
            double t = ta;
            while (mu > 0.0) {
                t += -std::log1p(-rng.uniform()) / mu;
                const double stop = std::min(t, tb);
                for (; i < n && hits[i].t < stop; ++i) out[i] *= acc;
                if (t >= tb) break;
                acc *= 1.0 - m.sigma_t(ray.at(t)) / mu;
                ++local.tracking_lookups;
            }
            for (; i < n && hits[i].t <= tb; ++i) out[i] *= acc;   // mu = 0: nothing to collide with
            return acc != 0.0;
        });
        const double rest = exact ? std::exp(-acc) : acc;
        for (; i < n; ++i) out[i] *= rest;
    }
}

Rgb PointBeamGather::in_scattering(const Ray& ray, double t_end, RegionMask region, Rng& rng, bool* starved) const {
    // A region with discs answers every segment (0 where none is crossed); one without any has no
    // estimate: the caller gathers the segment otherwise (as a starved point map).
    const Part* part = part_of(region);
    const bool none = part == nullptr || part->bvh.size() == 0;
    if (starved) *starved = none;
    if (none) return Rgb::Zero();
    const PhotonMap& map = *part->map;
    Local& local = local_.local();
    std::vector<Hit>& hits = local.hits;
    hits.clear();
    part->bvh.for_each_crossed_ball(ray.origin, ray.dir, t_end, [&](uint32_t index, double t, double d2, double r) {
        hits.push_back({t, d2, r, index});
    });
    ++local.queries;
    local.crossed += hits.size();
    if (hits.empty()) return Rgb::Zero();
    // In order along the ray, ties by index: one tracking pass serves every photon, and the random
    // stream is consumed in an order that does not depend on the BVH's traversal.
    std::sort(hits.begin(), hits.end(),
              [](const Hit& a, const Hit& b) { return a.t < b.t || (a.t == b.t && a.index < b.index); });
    transmittances(ray, hits, local.transmittance, rng, local);
    Rgb sum = Rgb::Zero();
    for (size_t i = 0; i < hits.size(); ++i) {
        const Hit& h = hits[i];
        const double r2 = h.r * h.r;
        const double w = local.transmittance[i] * kernel_.weight(h.d2 / r2, 2) / (kPi * r2);
        if (w == 0.0) continue;
        const double cos_theta = map.direction(h.index).dot(-ray.dir);
        Rgb f;
        if (foot_point_) {
            const Vec3 y = ray.at(h.t);
            f = scattering(y, cos_theta);
            if ((f == 0.0).all()) continue;
            f /= disc_sigma_t(y, ray.dir, h.r);   // positive: the foot is in a medium
        } else {
            f = albedo_phase(map.position(h.index), cos_theta);
        }
        if ((f == 0.0).all()) continue;
        sum += w * map.power(h.index) * f;
    }
    return sum;
}

PointBeamGatherStats PointBeamGather::stats() const {
    PointBeamGatherStats s = built_;
    for (const Local& l : local_) {
        s.queries += l.queries;
        s.crossed += l.crossed;
        s.tracking_lookups += l.tracking_lookups;
    }
    return s;
}

void PointBeamGather::report_build(RunStats* stats, std::ostream* log) const {
    const PointBeamGatherStats b = this->stats();
    if (stats) {
        stats->phase("build_radii", b.radii_seconds);
        stats->phase("build_beam_bvh", b.bvh_seconds);
    }
    if (!log) return;
    *log << "beam: radii (beam_k = " << b.k << ") " << b.radii_seconds << " s, BVH over " << b.photons << " discs";
    if (split_) *log << " in " << b.regions << " regions (glass interfaces: a segment crosses its own region's)";
    *log << " " << b.bvh_seconds << " s; " << b.total_bytes_per_photon << " bytes/photon (map " << b.map_bytes_per_photon
         << " + BVH " << b.bvh_bytes_per_photon << ")\n";
    // A map of at most beam_k photons has no disc: its segments gather like "march", whose points take
    // NEE and a continued path where the map is starved (unbiased; single scattering by NEE as here).
    if (!usable() && scene_.has_media())
        *log << "warning: photons.beam_k = " << b.k << " is not below the " << map_.size()
             << " volume photons stored" << (split_ ? " in any region" : "")
             << ": no photon has a beam_k-th neighbour, so this pass gathers like \"march\"\n";
}

void PointBeamGather::add_to(RunStats& run, std::ostream* log) const {
    PointBeamGatherStats total = stats();   // this pass's sizes, the run's times and counts
    if (const PointBeamGatherStats* before = run.sections.find<PointBeamGatherStats>()) total.add_run_totals(*before);
    run.sections.get<PointBeamGatherStats>() = total;
    if (log)
        *log << "beam: " << total.queries << " segment queries crossed " << total.crossed << " photon discs ("
             << (total.queries ? double(total.crossed) / double(total.queries) : 0.0) << " per query)\n";
}

std::unique_ptr<SegmentGather> build_point_beam_gather(SegmentGatherInputs& in) {
    return std::make_unique<PointBeamGather>(in.scene, in.volume, size_t(in.settings.beam_k), in.settings.estimator.kernel(),
                                             in.max_radius, in.settings.max_radius_mfp, in.disc_scale, in.volume_regions);
}

void PointBeamGatherStats::add_run_totals(const PointBeamGatherStats& earlier) {
    radii_seconds += earlier.radii_seconds;
    bvh_seconds += earlier.bvh_seconds;
    queries += earlier.queries;
    crossed += earlier.crossed;
    tracking_lookups += earlier.tracking_lookups;
}

void PointBeamGatherStats::write(RunRecord& record) const {
    record.set("photons.beam.k", k);
    record.set("photons.beam.photons", photons);
    record.set("photons.beam.regions", regions);
    record.set("photons.beam.bvh_bytes", bvh_bytes);
    record.set("photons.beam.bvh_bytes_per_photon", bvh_bytes_per_photon);
    record.set("photons.beam.map_bytes_per_photon", map_bytes_per_photon);
    record.set("photons.beam.total_bytes_per_photon", total_bytes_per_photon);
    record.set("photons.beam.radii_seconds", radii_seconds);
    record.set("photons.beam.bvh_seconds", bvh_seconds);
    record.set("photons.beam.queries", queries);
    record.set("photons.beam.crossed", crossed);
    record.set("photons.beam.tracking_lookups", tracking_lookups);
}

}  // namespace vpm
