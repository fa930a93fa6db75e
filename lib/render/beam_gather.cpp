#include "render/beam_gather.h"

#include <algorithm>
#include <cmath>

#include "core/henyey_greenstein.h"
#include "core/progress.h"
#include "photon/photon_radii.h"

namespace vpm {

BeamGather::BeamGather(const Scene& scene, const PhotonMap& map, size_t k, const Kernel& kernel, double max_radius,
                       double max_radius_mfp)
    : scene_(scene), map_(map), kernel_(kernel) {
    const Timer radii_timer;
    std::vector<double> radii = photon_radii(map, k);
    std::vector<Vec3> centres(map.size());
    for (size_t i = 0; i < map.size(); ++i) {
        centres[i] = map.position(i);
        double r = std::min(radii[i], max_radius);
        if (max_radius_mfp > 0.0 && std::isfinite(r)) {
            // The collision gather's bound (photon/bounded_radius.h), per photon: it depends on x_i
            // only, so the radius stays independent of the query.
            double sigma_t = 0.0;
            for (const auto& m : scene.media) sigma_t += m->sigma_t(centres[i]);
            if (sigma_t > 0.0) r = std::min(r, max_radius_mfp / sigma_t);
        }
        radii[i] = r;
    }
    built_.radii_seconds = radii_timer.seconds();
    const Timer bvh_timer;
    bvh_ = PhotonDiscBvh(centres, radii);
    built_.bvh_seconds = bvh_timer.seconds();
    built_.k = k;
    built_.photons = bvh_.size();
    built_.bvh_bytes = bvh_.memory_bytes();
    const double n = double(std::max<size_t>(map.size(), 1));
    built_.bvh_bytes_per_photon = double(built_.bvh_bytes) / n;
    built_.map_bytes_per_photon = double(map.memory_bytes()) / n;
    built_.total_bytes_per_photon = built_.bvh_bytes_per_photon + built_.map_bytes_per_photon;
}

Rgb BeamGather::scattering(const Vec3& x, double cos_theta) const {
    if (scene_.media.size() == 1) {
        const Medium& m = *scene_.media.front();
        return m.albedo() * hg_eval(cos_theta, m.g());
    }
    // Overlapping media: photons of all of them share the map, in proportion to each one's sigma_t.
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

Rgb BeamGather::in_scattering(const Ray& ray, double t_end, Rng& rng) const {
    Local& local = local_.local();
    std::vector<Hit>& hits = local.hits;
    hits.clear();
    bvh_.for_each_crossed_ball(ray.origin, ray.dir, t_end, [&](uint32_t index, double t, double d2, double r) {
        hits.push_back({t, d2, r, index});
    });
    ++local.queries;
    local.crossed += hits.size();
    if (hits.empty()) return Rgb::Zero();
    // In order along the ray: one transmittance estimate per interval, and the random stream
    // consumed in an order that does not depend on the BVH's traversal.
    std::sort(hits.begin(), hits.end(),
              [](const Hit& a, const Hit& b) { return a.t < b.t || (a.t == b.t && a.index < b.index); });
    Rgb sum = Rgb::Zero();
    double transmittance = 1.0, t_prev = 0.0;
    for (const Hit& h : hits) {
        if (h.t > t_prev) {
            for (const auto& m : scene_.media) transmittance *= m->transmittance(Ray{ray.at(t_prev), ray.dir}, h.t - t_prev, rng);
            local.transmittance_calls += scene_.media.size();
            t_prev = h.t;
        }
        if (transmittance == 0.0) break;
        const double r2 = h.r * h.r;
        const double w = kernel_.weight(h.d2 / r2, 2) / (kPi * r2);
        if (w == 0.0) continue;
        const Vec3 x = map_.position(h.index);
        sum += (transmittance * w) * map_.power(h.index) * scattering(x, map_.direction(h.index).dot(-ray.dir));
    }
    return sum;
}

BeamGatherStats BeamGather::stats() const {
    BeamGatherStats s = built_;
    for (const Local& l : local_) {
        s.queries += l.queries;
        s.crossed += l.crossed;
        s.transmittance_calls += l.transmittance_calls;
    }
    return s;
}

}  // namespace vpm
