#pragma once
// Equiangular sampling (Kulla & Fajardo, "Importance Sampling Techniques for Path Tracing in
// Participating Media", EGSR 2012) of the single scattering from lights that emit from one point
// (point and spot lights: Light::delta_position) along a ray segment, combined with the caller's
// own distance sampling by the balance heuristic, one sample of each strategy (render.equiangular).
//
// Why: next-event estimation from points placed by distance alone weighs I / d^2 at a point d away
// from the light, and the integral of d^-4 over a ball around the light diverges: the estimate has
// infinite variance wherever paths pass near a point light inside a medium
// (configs/inside_large_sphere.toml spread 0.95 .. 1.05 of its mean over seeds).
//
// On the part [a, b] of the segment within the media's bounds, with h the light's distance from the
// ray's line and t0 the foot of the perpendicular, theta(t) = atan((t - t0) / h):
//
//   p_e(t) = h / ((theta_b - theta_a) (h^2 + (t - t0)^2)),   t = t0 + h tan(theta_a + u (theta_b - theta_a))
//
// (b may be infinite: theta_b = pi / 2). p_e is proportional to 1 / d^2, so the sample's weight
// stays bounded near the light.
//
// The other strategy is the caller's: a density q(t, m) with which it places points in medium m that
// take NEE (the free flight: sigma_t,m(t) T(t) with T over all media; the march: its point count over
// its mass times sigma_t,m(t) T_m(t), transport/march_points.h). Its NEE to such a light weighs
// q / (q + p_e) (SegmentPoint), and the equiangular sample adds, per medium m at the sampled t,
//
//   T(t) sigma_s,m(t) phase_m L_light(t) T_shadow / (p_e(t) + q(t, m)):
//
// the two weights sum to one at every (t, m), so the sum stays unbiased for the same integral.
// T(t) is exact (the media's optical-depth profiles, cut where the depth reaches
// OpticalDepthProfile::kEnoughDepth: T < 5e-18 there); the shadow ray's by the scene's tracking.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/henyey_greenstein.h"
#include "core/math.h"
#include "core/sampling/rng.h"
#include "scene/scene.h"

namespace vpm {

class EquiangularSegment {
public:
    // The point and spot lights of the scene that [0, t_end] of `ray` (unit dir) passes within the
    // media's bounds. t_end may be kInfinity.
    EquiangularSegment(const Scene& scene, const Ray& ray, double t_end);
    // No light to sample on this segment: callers skip both the sample and the weights.
    bool empty() const { return lights_.empty(); }

    // p_e(t) of scene.lights[light_index]; 0 for a light this segment does not sample and t outside [a, b].
    double pdf(size_t light_index, double t) const;
    // The weight of the other strategy's NEE to scene.lights[light_index] from its point at t,
    // placed with density q there.
    double distance_weight(size_t light_index, double t, double q) const {
        const double pe = pdf(light_index, t);
        return pe > 0.0 ? q / (q + pe) : 1.0;
    }

    // The free flight's density at (t, m) on this segment, sigma_t,m(t) exp(-tau over all media), for
    // the collision that medium m's sigma_t_m gave at t.
    double free_flight_density_at(double t, double sigma_t_m) const;

    // The optical depth of scene.media[medium_index] over (0, t) (exact, as in_scattering's).
    double medium_depth(size_t medium_index, double t) const;
    // The index in scene.media of `medium`.
    size_t medium_index(const Medium& medium) const;

    // The other strategy's density at the sampled t in medium m: other(m, sigma_t_m, tau_m, tau_all),
    // tau_m that medium's optical depth over (0, t), tau_all every medium's.
    // One equiangular sample per light (one uniform each); `rays` counts the shadow rays.
    template <class OtherDensity>
    Rgb in_scattering(Rng& rng, uint64_t& rays, OtherDensity&& other) const;

private:
    struct Entry {
        size_t index;   // in scene.lights
        double t0, h, theta_a, theta_b;
    };
    double entry_pdf(const Entry& e, double t) const;
    // The optical depth over (0, t) of each medium (into taus) and their sum.
    double depths(double t, std::vector<double>& taus) const;

    const Scene& scene_;
    Ray ray_;
    double a_ = 0.0, b_ = 0.0;
    std::vector<Entry> lights_;
};

// Where the other strategy's NEE is taken: its segment (null: no equiangular sample there, weight
// 1), the point's t on it and the density q with which the point was placed.
struct SegmentPoint {
    const EquiangularSegment* segment = nullptr;
    double t = 0.0;
    double density = 0.0;
    double weight(size_t light_index) const { return segment->distance_weight(light_index, t, density); }
};

// The free flight's density at (t, m): sigma_t,m(t) exp(-tau over all media).
inline double free_flight_density(double sigma_t_m, double tau_all) { return sigma_t_m * std::exp(-tau_all); }

// The light's incident radiance at ray.at(t) times the shadow ray's transmittance, its direction wi;
// lit = false where the light does not reach the point (outside a spot's cone). Counts the shadow ray.
Rgb equiangular_light_sample(const Scene& scene, const Ray& ray, size_t light_index, double t, Rng& rng,
                             uint64_t& rays, Vec3& wi, bool& lit);

template <class OtherDensity>
Rgb EquiangularSegment::in_scattering(Rng& rng, uint64_t& rays, OtherDensity&& other) const {
    Rgb sum = Rgb::Zero();
    thread_local std::vector<double> taus;
    for (const Entry& e : lights_) {
        const double u = rng.uniform();
        const double t = e.t0 + e.h * std::tan(e.theta_a + u * (e.theta_b - e.theta_a));
        const double pe = entry_pdf(e, t);
        if (!(pe > 0.0)) continue;   // rounded out of [a, b]
        const Vec3 x = ray_.at(t);
        bool any = false;
        for (const auto& m : scene_.media) any = any || m->sigma_t(x) > 0.0;
        if (!any) continue;
        Vec3 wi;
        bool lit = false;
        const Rgb li = equiangular_light_sample(scene_, ray_, e.index, t, rng, rays, wi, lit);
        if (!lit) continue;
        const double tau_all = depths(t, taus);
        const double tr = std::exp(-tau_all);
        if (!(tr > 0.0)) continue;
        for (size_t i = 0; i < scene_.media.size(); ++i) {
            const Medium& m = *scene_.media[i];
            const double s = m.sigma_t(x);
            if (!(s > 0.0)) continue;
            const double phase = hg_eval((-wi).dot(-ray_.dir), m.g());
            const double q = other(i, s, taus[i], tau_all);
            sum += li * m.albedo() * (tr * s * phase / (pe + q));
        }
    }
    return sum;
}

}  // namespace vpm
