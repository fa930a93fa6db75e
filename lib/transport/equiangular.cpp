#include "transport/equiangular.h"

#include <algorithm>

namespace vpm {

EquiangularSegment::EquiangularSegment(const Scene& scene, const Ray& ray, double t_end) : scene_(scene), ray_(ray) {
    a_ = kInfinity;
    b_ = -kInfinity;
    for (const auto& m : scene.media) {
        double t0 = 0.0, t1 = 0.0;
        if (!m->bounds().intersect(ray, t_end, t0, t1)) continue;
        a_ = std::min(a_, t0);
        b_ = std::max(b_, t1);
    }
    if (!(b_ > a_)) return;
    for (size_t i = 0; i < scene.lights.size(); ++i) {
        Vec3 p;
        if (!scene.lights[i]->delta_position(p)) continue;
        const Vec3 d = p - ray.origin;
        const double t0 = d.dot(ray.dir);
        const double h = (d - t0 * ray.dir).norm();
        // On the ray's line the density has no finite normalisation: the other strategy alone.
        if (!(h > 0.0) || !std::isfinite(h)) continue;
        const double theta_a = std::atan2(a_ - t0, h);
        const double theta_b = std::isinf(b_) ? 0.5 * kPi : std::atan2(b_ - t0, h);
        if (!(theta_b > theta_a)) continue;
        lights_.push_back(Entry{i, t0, h, theta_a, theta_b});
    }
}

double EquiangularSegment::entry_pdf(const Entry& e, double t) const {
    if (!(t >= a_ && t <= b_)) return 0.0;
    const double dt = t - e.t0;
    return e.h / ((e.theta_b - e.theta_a) * (e.h * e.h + dt * dt));
}

double EquiangularSegment::pdf(size_t light_index, double t) const {
    for (const Entry& e : lights_)
        if (e.index == light_index) return entry_pdf(e, t);
    return 0.0;
}

double EquiangularSegment::depths(double t, std::vector<double>& taus) const {
    thread_local OpticalDepthProfile profile;
    taus.assign(scene_.media.size(), 0.0);
    double total = 0.0;
    for (size_t i = 0; i < scene_.media.size(); ++i) {
        scene_.media[i]->optical_depth_profile(ray_, t, profile);
        if (!profile.empty()) taus[i] = profile.total();
        total += taus[i];
    }
    return total;
}

double EquiangularSegment::free_flight_density_at(double t, double sigma_t_m) const {
    thread_local std::vector<double> taus;
    return free_flight_density(sigma_t_m, depths(t, taus));
}

double EquiangularSegment::medium_depth(size_t medium_index, double t) const {
    thread_local OpticalDepthProfile profile;
    scene_.media[medium_index]->optical_depth_profile(ray_, t, profile);
    return profile.empty() ? 0.0 : profile.total();
}

size_t EquiangularSegment::medium_index(const Medium& medium) const {
    size_t i = 0;
    while (i + 1 < scene_.media.size() && scene_.media[i].get() != &medium) ++i;
    return i;
}

Rgb equiangular_light_sample(const Scene& scene, const Ray& ray, size_t light_index, double t, Rng& rng,
                             uint64_t& rays, Vec3& wi, bool& lit) {
    const Light& light = *scene.lights[light_index];
    const Vec3 x = ray.at(t);
    LightSample ls;
    lit = light.sample_incident(x, rng, ls) && !(ls.weight == 0.0).all();
    if (!lit) return Rgb::Zero();
    wi = ls.wi;
    ++rays;
    return ls.weight * scene.transmittance(Ray{x, ls.wi}, ls.distance, rng, &light);
}

}  // namespace vpm
