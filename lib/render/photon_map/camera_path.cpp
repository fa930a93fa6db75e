#include "render/photon_map/camera_path.h"

#include <algorithm>
#include <optional>
#include <vector>

#include "core/henyey_greenstein.h"
#include "render/photon_map/gathers/segment_gather.h"
#include "scene/dielectric_regions.h"
#include "scene/materials/material.h"
#include "transport/direct_light.h"
#include "transport/equiangular.h"
#include "transport/march_points.h"
#include "transport/segment_direct_light.h"
#include "transport/single_scattering.h"
#include "transport/specular_step.h"
#include "transport/walk_steps.h"

namespace vpm {

namespace {

double total_sigma_t(const Scene& scene, const Vec3& x) {
    double sigma_t = 0.0;   // overlapping media: photons of all of them are in the map
    for (const auto& m : scene.media) sigma_t += m->sigma_t(x);
    return sigma_t;
}

}  // namespace

Rgb CameraPath::single_scattering(const Vec3& x, const Vec3& dir, double g, bool goes_on, Rng& rng, CameraCounters& c,
                                  const SegmentPoint* at) const {
    if (goes_on) return direct_light_in_medium(scene_, x, dir, g, rng, settings_.walk.mis, at);
    if (!both_strategies_) return direct_light_in_medium(scene_, x, dir, g, rng, false, at);
    uint64_t rays = 0;
    const Rgb l = single_scattering_both_strategies(scene_, x, dir, g, rng, rays, at);
    c.rays += rays - 1;   // the caller counts one
    return l;
}

CameraTotals sum_counters(const CounterSet& counters) {
    CameraTotals t;
    for (const CameraCounters& l : counters) {
        t.estimates.merge(l.estimates);
        t.surface_stats.merge(l.surface_stats);
        t.continued += l.continued;
        t.march_wide += l.march_wide;
        t.rays += l.rays;
        t.march_points += l.march_points;
        t.map_used += l.map_used;
        t.march_weight_max = std::max(t.march_weight_max, l.march_weight_max);
        t.march_weight_sum += l.march_weight_sum;
    }
    return t;
}

VolumeEstimator CameraPath::volume_in(RegionMask region) const {
    const VolumeEstimator& v = maps_.volume;
    if (!maps_.volume_regions) return v;
    return VolumeEstimator{maps_.volume_regions->at(region), v.decision, v.k, v.estimator, v.max_radius, v.max_radius_mfp,
                           v.extinction, v.leave_group_out, v.ball, v.neighbourhood, scene_.surfaces.get(), region};
}

const PhotonMap* CameraPath::surface_in(RegionMask region) const {
    return maps_.surface && maps_.surface_regions ? &maps_.surface_regions->at(region) : maps_.surface;
}

Rgb CameraPath::trace(const Ray& first_ray, int first_depth, Rng& rng, CameraCounters& c,
                       const EmissionWeighting& first_emission) const {
    // The path's region (scene/dielectric_regions.h): where it starts (the camera, or the march point
    // a continued path leaves), toggled at every refraction through glass.
    const bool regions = maps_.volume_regions || maps_.surface_regions || (maps_.segment && maps_.segment->split_by_region());
    const RegionMask start_region = regions ? region_at(scene_.surfaces.get(), first_ray.origin) : 0;
    // transport/mis.h. A path started deeper (first_depth > 0) continues from a march point: the
    // emission it meets counts as that point's NEE was weighted (transport/single_scattering.h).
    PathState state{first_ray, Rgb::Ones(), Rgb::Zero(), first_emission, start_region};
    state.from_camera = first_depth == 0;
    state.splits_left = state.from_camera ? settings_.glass_splits : 0;
    walk(state, first_depth, rng, c);
    return state.radiance;
}

void CameraPath::walk(PathState& state, int first_depth, Rng& rng, CameraCounters& c) const {
    const int max_depth = settings_.walk.max_depth;
    Ray& ray = state.ray;
    Rgb& throughput = state.throughput;
    Rgb& radiance = state.radiance;
    EmissionWeighting& emission = state.emission;
    RegionMask& region = state.region;
    for (int depth = first_depth;; ++depth) {
        const PathVertex v = next_vertex(scene_, ray, rng);
        ++c.rays;
        const MediumEvent& event = v.medium;
        const SurfaceHit& hit = v.hit;
        const double t_end = v.on_surface ? hit.t : kInfinity;
        // A path continued from a march point (first_depth > 0) gathers at its collisions: marching
        // again would branch at every point, a tree that grows without bound where every ball is wide.
        const bool march = state.from_camera && marches(ray, t_end);
        bool beam = maps_.segment != nullptr;
        // A segment gather with no estimate here (photon beams with balloon widths crossed by fewer
        // than k beams, a region with no discs or beams) is gathered as the collision gather's are
        // (the path goes on from its free flight, as a starved point map makes it), not counted as 0.
        const bool last = max_depth >= 0 && depth + 1 > max_depth;   // no scattering past this segment
        Rgb beams = Rgb::Zero();
        const Rgb* taken = nullptr;
        if (beam && !last) {
            bool starved = false;
            beams = maps_.segment->in_scattering(ray, t_end, region, rng, &starved);
            taken = &beams;
            if (starved) beam = false;
        }
        std::optional<EquiangularSegment> segment;
        if (settings_.walk.equiangular && settings_.direct == DirectLighting::nee && !march && !beam && !last &&
            scene_.has_media())
            equiangular_segment(t_end, rng, c, state, segment);
        if ((march || beam) && (!v.on_surface || hit.emitter)) {
            light_behind_gathered_segment(v, march, !last, depth, taken, rng, c, state);
            break;
        }
        if (v.escaped()) {
            radiance += throughput * escaped_radiance(scene_, ray.dir, emission);
            if (march && !last) radiance += throughput * march_in_scattering(ray, kInfinity, depth, region, rng, c);
            if (beam && !last) radiance += throughput * beam_in_scattering(ray, kInfinity, rng, c, *taken);
            break;
        }
        if (!event && hit.emitter) radiance += throughput * emitted_radiance(scene_, ray, hit, emission);   // black: ends below
        if (last) break;
        if (march) {
            // The medium's in-scattering along this segment comes from the march; the collision
            // sampled above only decides whether the path reaches the surface behind (probability T).
            radiance += throughput * march_in_scattering(ray, t_end, depth, region, rng, c);
            if (event) break;
        }
        if (beam) {   // the same rule with the whole segment in one query
            radiance += throughput * beam_in_scattering(ray, t_end, rng, c, *taken);
            if (event) break;
        }
        if (event) {
            if (collision_step(event, depth, segment ? &*segment : nullptr, rng, c, state) == Step::next) continue;
            break;
        }
        if (hit.specular) {   // mirror or glass (transport/specular_step.h): on to the chain's next vertex
            if (specular_step(hit, depth, rng, c, state) == Step::next) continue;
            break;
        }
        if (diffuse_step(hit, depth, rng, c, state) == Step::next) continue;
        break;
    }
}

CameraPath::Step CameraPath::specular_step(const SurfaceHit& hit, int depth, Rng& rng, CameraCounters& c,
                                           PathState& p) const {
    const int rr_depth = settings_.walk.rr_depth;
    MaterialSample events[2];
    if (p.splits_left > 0 && hit.specular->both_events(p.ray.dir, hit.normal, hit.exiting, Transport::radiance, events)) {
        --p.splits_left;
        PathState reflected = p;
        reflected.radiance = Rgb::Zero();
        if (camera_specular_branch(hit, events[0], reflected.ray, reflected.throughput, reflected.emission, depth + 1,
                                   rr_depth, rng, &reflected.radiance_scale)) {
            walk(reflected, depth + 1, rng, c);
            p.radiance += reflected.radiance;
        }
        if (!camera_specular_branch(hit, events[1], p.ray, p.throughput, p.emission, depth + 1, rr_depth, rng,
                                    &p.radiance_scale))
            return Step::end;
    } else if (!camera_specular_step(hit, p.ray, p.throughput, p.emission, depth + 1, rr_depth, rng, &p.radiance_scale)) {
        return Step::end;
    }
    p.region = region_after_specular(p.region, hit, p.ray.dir);
    return Step::next;
}

// The collision gather's segments with direct = "nee", where every collision takes NEE: point and spot
// lights are also sampled equiangularly along it (transport/equiangular.h). The march's and the beam's
// segments do the same in march_in_scattering and segment_direct_light.
void CameraPath::equiangular_segment(double t_end, Rng& rng, CameraCounters& c, PathState& p,
                                     std::optional<EquiangularSegment>& segment) const {
    segment.emplace(scene_, p.ray, t_end);
    if (segment->empty()) {
        segment.reset();
        return;
    }
    p.radiance += p.throughput * segment->in_scattering(rng, c.rays, [](size_t, double s, double, double tau) {
        return free_flight_density(s, tau);
    });
}

// A gathered segment (march or beams) that ends on a light or escapes: its in-scattering is gathered
// apart, so the sky or area light behind it is weighed by the exact transmittance, not found by the
// free flight's trial (transport/seen_through.h). The light is black: the path ends here either way.
void CameraPath::light_behind_gathered_segment(const PathVertex& v, bool march, bool gathers, int depth, const Rgb* taken,
                                               Rng& rng, CameraCounters& c, PathState& p) const {
    const double t_end = v.on_surface ? v.hit.t : kInfinity;
    if (march && gathers) {
        // The march's profiles give the segment's optical depth: one walk, not two.
        double tau = 0.0;
        const Rgb in = march_in_scattering(p.ray, t_end, depth, p.region, rng, c, &tau);
        p.radiance += p.throughput * seen_through_depth(scene_, p.ray, v.on_surface, v.hit, p.emission, tau, c.rays);
        p.radiance += p.throughput * in;
        return;
    }
    p.radiance += p.throughput * seen_through(scene_, p.ray, v.on_surface, v.hit, p.emission, c.profile, c.rays);
    if (gathers) p.radiance += p.throughput * beam_in_scattering(p.ray, t_end, rng, c, *taken);
}

CameraPath::Step CameraPath::collision_step(const MediumEvent& event, int depth, const EquiangularSegment* segment, Rng& rng,
                                            CameraCounters& c, PathState& p) const {
    const Vec3 x = p.ray.at(event.t);
    const Medium& m = *event.medium;
    const Rgb weight = p.throughput * m.albedo();
    if ((weight == 0.0).all()) return Step::end;
    const bool nee = settings_.direct == DirectLighting::nee;
    const double sigma_t = total_sigma_t(scene_, x);
    // The query draws no random numbers, so it runs first: a path that goes on from x weighs its NEE
    // against the bounce (render.mis) like the path tracer's (transport/single_scattering.h); one that
    // ends on the map weighs it 1.
    VolumeEstimate b;
    if (sigma_t > 0.0) b = volume_in(p.region).estimate(x, -p.ray.dir, m.g(), sigma_t, c.scratch, c.estimates);
    const bool goes_on = b.rule == BoundedQuery::continue_path;
    if (nee) {
        if (segment) {
            const SegmentPoint at{segment, event.t, segment->free_flight_density_at(event.t, m.sigma_t(x))};
            p.radiance += weight * single_scattering(x, p.ray.dir, m.g(), goes_on, rng, c, &at);
        } else {
            p.radiance += weight * single_scattering(x, p.ray.dir, m.g(), goes_on, rng, c);
        }
        ++c.rays;
    }
    if (!(sigma_t > 0.0) || b.rule == BoundedQuery::zero) return Step::end;
    if (!goes_on) {
        p.radiance += weight * b.incident;
        ++c.map_used;
        return Step::end;
    }
    ++c.continued;   // too few photons: scatter and go on
    if (!nee) p.radiance += weight * direct_light_in_medium(scene_, x, p.ray.dir, m.g(), rng, settings_.walk.mis);
    p.throughput = weight;
    const double u1 = rng.uniform(), u2 = rng.uniform();
    const Vec3 wo = hg_sample(p.ray.dir, m.g(), u1, u2);
    p.emission = continued_emission(settings_.walk.mis, x, p.ray.dir, wo, m.g());
    p.ray = Ray{x, wo};
    return survive_roulette(p.throughput, depth + 1, settings_.walk.rr_depth, rng, p.radiance_scale) ? Step::next : Step::end;
}

CameraPath::Step CameraPath::diffuse_step(const SurfaceHit& hit, int depth, Rng& rng, CameraCounters& c, PathState& p) const {
    if ((hit.reflectance == 0.0).all()) return Step::end;
    // The surface photon map gives the light the path would gather. A map of fewer than k photons
    // (empty or starved) has no kNN disc anywhere: the path goes on as under final_gather.
    const PhotonMap* surface = surface_in(p.region);
    if (surface && surface->size() >= maps_.k) {
        if (settings_.direct == DirectLighting::nee) p.radiance += p.throughput * direct_light_on_surface(scene_, hit, rng);
        const Estimate<Rgb> e =
            settings_.neighbourhood == Neighbourhood::walks
                ? estimate_surface_irradiance_walks(*surface, hit.position, hit.normal, *maps_.surface_estimator,
                                                    maps_.k, maps_.max_radius, c.scratch.buffers, &c.surface_stats)
                : estimate_surface_irradiance(*surface, hit.position, hit.normal, *maps_.surface_estimator,
                                              maps_.k, maps_.max_radius, c.scratch.buffers, &c.surface_stats);
        p.radiance += p.throughput * hit.reflectance * (e.value / (kPi * surface_disc_share(hit, e.radius, p.region)));
        ++c.map_used;
        return Step::end;
    }
    p.radiance += p.throughput * direct_light_on_surface(scene_, hit, rng, settings_.walk.mis);
    p.throughput *= hit.reflectance;
    p.ray = diffuse_bounce(hit, rng);
    p.emission = EmissionWeighting::after(settings_.walk.mis, hit.position, std::max(0.0, p.ray.dir.dot(hit.normal)) * kInvPi);
    return survive_roulette(p.throughput, depth + 1, settings_.walk.rr_depth, rng, p.radiance_scale) ? Step::next : Step::end;
}

// The share of a region map's kNN disc that lies in the path's region (glass standing on the surface
// cuts it: scene/dielectric_regions.h); the whole map's disc is not divided.
double CameraPath::surface_disc_share(const SurfaceHit& hit, double radius, RegionMask region) const {
    if (!maps_.surface_regions) return 1.0;
    const Vec3 off = hit.position + (hit.epsilon + 1e-4 * radius) * hit.normal;
    return region_disc_fraction(scene_.surfaces.get(), off, hit.normal, radius, region);
}

bool CameraPath::marches(const Ray& ray, double t_end) const {
    if (maps_.gather == GatherMode::march) return true;
    if (maps_.gather != GatherMode::threshold) return false;
    // gather = "threshold". Thin along this segment: every ray
    // gathers at a few points. Thick: the collision gather puts its one query where the light is and
    // bounds its ball in mean free paths, while the march's points, all a few mean free paths apart,
    // would mostly take continued paths. The walk stops once the threshold is passed,
    // so thick segments, the collision gather's, pay for a few majorant pieces only.
    const double limit = settings_.march_max_optical_depth;
    double depth = 0.0;
    for (const auto& m : scene_.media) {
        m->majorant_pieces(ray, t_end, [&](double ta, double tb, double mu) {
            depth += mu * (tb - ta);
            return depth <= limit;
        });
        if (depth > limit) return false;
    }
    return true;
}

Rgb CameraPath::march_in_scattering(const Ray& ray, double t_end, int depth, RegionMask region, Rng& rng,
                                    CameraCounters& c, double* optical_depth) const {
    // Per medium, m stratified points with the free-flight density of its exact extinction
    // (transport/march_points.h): each weighs albedo P / m times the other media's transmittance,
    // P = 1 - exp(-tau(t_end)), so weights stay bounded in any density field; m = n or fewer where
    // P is small (photons.march_points, transport/march_count.h).
    const int n = settings_.gather_queries;
    Rgb sum = Rgb::Zero();
    // With direct = "nee" every point takes NEE: point and spot lights are also sampled equiangularly
    // along the segment, each point's NEE to them weighted with the march's density there.
    std::optional<EquiangularSegment> segment;
    std::vector<MarchMass> masses;
    if (settings_.walk.equiangular && settings_.direct == DirectLighting::nee) {
        segment.emplace(scene_, ray, t_end);
        if (segment->empty())
            segment.reset();
        else
            masses.assign(scene_.media.size(), MarchMass{});
    }
    // The profile counts as one tracked segment per point, like each other medium's.
    for_each_march_point(scene_, ray, t_end, n, settings_.march_points, rng, scene_.media.size(), c.rays,
                         [&](const Medium& medium, double t, double others, MarchMass mass) {
                             // Relative to the weight in the medium alone.
                             c.march_weight_max = std::max(c.march_weight_max, others);
                             c.march_weight_sum += others;
                             ++c.march_points;
                             const Vec3 x = ray.at(t);
                             const Rgb weight = (others * mass.mass / mass.divisor) * medium.albedo();
                             if (!segment) {
                                 sum += weight * incident_at_march_point(x, ray.dir, medium.g(), total_sigma_t(scene_, x), weight, depth, region,
                                                                         rng, c);
                                 return;
                             }
                             const double tau = segment->medium_depth(segment->medium_index(medium), t);
                             const SegmentPoint at{&*segment, t, march_density(mass, medium.sigma_t(x), tau)};
                             sum += weight * incident_at_march_point(x, ray.dir, medium.g(), total_sigma_t(scene_, x), weight,
                                                                     depth, region, rng, c, &at);
                         },
                         optical_depth, segment ? masses.data() : nullptr);
    if (segment)
        sum += segment->in_scattering(rng, c.rays, [&](size_t i, double sigma_t, double tau_m, double) {
            return march_density(masses[i], sigma_t, tau_m);
        });
    return sum;
}

Rgb CameraPath::incident_at_march_point(const Vec3& x, const Vec3& dir, double g, double sigma_t, const Rgb& weight,
                                        int depth, RegionMask region, Rng& rng, CameraCounters& c, const SegmentPoint* at) const {
    const bool nee = settings_.direct == DirectLighting::nee;
    Rgb in = Rgb::Zero();   // phase-weighted incident radiance at x
    // The collision gather's bound and rule (photon/estimate/bounded_radius.h) here: a ball spanning many mean
    // free paths averages the lit skin of a dense medium with its dark inside (biased low), so where
    // fewer than k photons lie within the bound the point takes the light a path would find instead,
    // NEE and one phase-sampled continuation, both unbiased for the same incident radiance; where
    // exactly k - 1 do, it takes 0, whose mass the k-1 correction already counts on the kNN side.
    // The choice depends on x and the map only; the query draws no random numbers, so NEE, weighted
    // as transport/single_scattering.h says, follows it.
    const VolumeEstimate b = volume_in(region).estimate(x, -dir, g, sigma_t, c.scratch, c.estimates);
    const bool wide = b.rule == BoundedQuery::continue_path;
    if (nee) {
        in += single_scattering(x, dir, g, wide, rng, c, at);
        ++c.rays;
    }
    if (b.rule == BoundedQuery::zero) return in;
    if (wide) {
        ++c.march_wide;
        if (!nee) in += direct_light_in_medium(scene_, x, dir, g, rng, settings_.walk.mis);
        ++c.rays;
        // Roulette on the point's weight: where it is small, so is the chance of paying for a path.
        const double q = std::min(1.0, weight.maxCoeff());
        if (rng.uniform() < q) {
            const double u1 = rng.uniform(), u2 = rng.uniform();
            const Vec3 wo = hg_sample(dir, g, u1, u2);
            in += trace(Ray{x, wo}, depth + 1, rng, c, continued_emission(settings_.walk.mis, x, dir, wo, g)) / q;
        }
        return in;
    }
    ++c.map_used;
    return in + b.incident;
}

Rgb CameraPath::beam_in_scattering(const Ray& ray, double t_end, Rng& rng, CameraCounters& c, const Rgb& taken) const {
    Rgb l = taken;
    if (settings_.direct == DirectLighting::nee)
        l += segment_direct_light(scene_, ray, t_end, settings_.gather_queries, rng, c.rays,
                                  settings_.walk.equiangular);
    return l;
}

}  // namespace vpm
