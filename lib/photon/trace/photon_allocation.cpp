#include "photon/trace/photon_allocation.h"

#include <algorithm>
#include <sstream>

#include "photon/estimate/estimators.h"
#include "photon/map/photon_map.h"
#include "transport/walk_steps.h"

namespace vpm {

LightAllocation power_allocation(const Scene& scene) {
    LightAllocation a;
    double sum = 0.0;
    for (const auto& l : scene.lights) {
        a.power_share.push_back(std::max(0.0, luminance(l->power())));
        sum += a.power_share.back();
    }
    for (double& p : a.power_share) p = sum > 0.0 ? p / sum : 1.0 / double(scene.lights.size());
    a.weights = a.power_share;
    a.importance.assign(scene.lights.size(), 0.0);
    return a;
}

LightAllocation importance_allocation(const Scene& scene, const PhotonTraceSettings& base) {
    LightAllocation a = power_allocation(scene);
    const size_t n_lights = scene.lights.size();
    if (n_lights < 2) return a;

    // Camera points: where camera paths first meet a medium or a surface.
    std::vector<Vec3> points;
    Rng rng(base.seed ^ 0x70696c6f74ULL, 0x63616d ^ base.stream_offset);
    const int w = scene.camera.width(), h = scene.camera.height();
    for (int i = 0; i < kPilotRays; ++i) {
        const Ray ray = scene.camera.generate_ray(rng.uniform() * w, rng.uniform() * h);
        const PathVertex v = next_vertex(scene, ray, rng);
        if (v.medium) points.push_back(ray.at(v.medium.t));
        else if (v.on_surface) points.push_back(v.hit.position);
    }
    a.pilot_camera_points = points.size();
    if (points.empty()) return a;

    // The region the camera sees: a ball around each camera point q of radius h_q, the distance to
    // its kPilotK-th nearest camera point (the points' own spacing there).
    std::vector<PhotonInput> as_photons(points.size());
    for (size_t i = 0; i < points.size(); ++i) as_photons[i].position = points[i];
    const PhotonMap camera_map(as_photons);
    NeighbourList list;
    std::vector<double> h2(camera_map.size(), 0.0);
    for (size_t i = 0; i < camera_map.size(); ++i) {
        camera_map.knn(camera_map.position(i), std::min(kPilotK + 1, camera_map.size()), kInfinity, list);
        h2[i] = list.items.back().d2;
    }

    std::vector<double> importance(n_lights, 0.0);
    for (size_t l = 0; l < n_lights; ++l) {
        if (a.power_share[l] <= 0.0) continue;
        PhotonTraceSettings ts = base;
        ts.count = kPilotPhotons;
        ts.seed = base.seed ^ (0x9e3779b97f4a7c15ULL * (l + 1));
        ts.progress = false;
        ts.on_chunk = nullptr;
        ts.light_weights.clear();
        ts.single_light = int(l);
        const PhotonTraceResult r = trace_photons(scene, ts);
        a.pilot_photons += r.paths;
        double sum = 0.0;   // stored power of light l inside the seen region
        for (const auto* photons : {&r.photons, &r.surface_photons})
            for (const PhotonInput& p : *photons) {
                if (camera_map.knn(p.position, 1, kInfinity, list) == 0) continue;
                if (list[0].d2 <= h2[list[0].index]) sum += luminance(p.power);
            }
        importance[l] = sum;
    }
    double total = 0.0;
    for (double v : importance) total += v;
    if (!(total > 0.0) || !std::isfinite(total)) return a;
    for (size_t l = 0; l < n_lights; ++l) {
        a.importance[l] = importance[l] / total;
        a.weights[l] = (1.0 - kPowerMix) * a.importance[l] + kPowerMix * a.power_share[l];
    }
    a.from_pilot = true;
    return a;
}

std::string LightAllocation::to_string() const {
    std::ostringstream s;
    s.precision(3);
    for (size_t l = 0; l < weights.size(); ++l)
        s << (l ? ", " : "") << "light " << l << ": " << 100.0 * weights[l] << "% of photons (power share "
          << 100.0 * power_share[l] << "%, importance " << 100.0 * importance[l] << "%)";
    s << (from_pilot ? "" : " [by power]");
    return s.str();
}

}  // namespace vpm
