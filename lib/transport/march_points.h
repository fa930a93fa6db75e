#pragma once
// Where the march (photons.gather = "march") gathers along a camera segment: n stratified points
// with the free-flight density of one medium's exact extinction,
//
//   p(t) = sigma_t(t) exp(-tau(t)) / P,   P = 1 - exp(-tau(tmax)),
//
// by inverting its optical-depth profile (scene/media/optical_depth_profile.h). The estimate
// sum_j T(t_j) sigma_s(t_j) L(t_j) / (n p(t_j)) then weighs each point albedo P / n times the
// other media's transmittance: this medium's transmittance and extinction cancel exactly, so the
// weights are bounded by albedo P / n in any density field, where points placed by a majorant's
// free flight weighed up to e^(tau_majorant - tau) times that.
#include <cmath>
#include <cstdint>
#include <vector>

#include "core/math.h"
#include "core/sampling/rng.h"
#include "scene/media/medium.h"
#include "scene/media/optical_depth_profile.h"
#include "scene/scene.h"
#include "transport/march_count.h"

namespace vpm {

// Fills ts with the points in increasing t (empty when the medium is not crossed) and returns P.
// Draws n uniforms from rng when P > 0, none otherwise. `profile` is scratch space.
double place_march_points(const Medium& medium, const Ray& ray, double tmax, int n, Rng& rng,
                          OpticalDepthProfile& profile, std::vector<double>& ts);

// Each point weighs mass / divisor (times the albedo and the other media's transmittance).
struct MarchMass {
    double mass = 0.0;   // P (fixed, mass), 1 (free_flight); 0 when the medium is not crossed
    int divisor = 1;
};

// The points as place_march_points, counted by `count`.
MarchMass place_counted_march_points(const Medium& medium, const Ray& ray, double tmax, int n, MarchCount count,
                                     Rng& rng, OpticalDepthProfile& profile, std::vector<double>& ts);

// The density with which those points lie at t in the medium, sigma_t there and tau its optical depth
// over (0, t): m.divisor / m.mass * sigma_t exp(-tau) (0 where it places none).
inline double march_density(const MarchMass& m, double sigma_t, double tau) {
    return m.mass > 0.0 ? m.divisor / m.mass * sigma_t * std::exp(-tau) : 0.0;
}

// Scratch space of one for_each_march_point call, kept by the thread for its later calls (a profile
// holds a piece per voxel cell crossed: growing a fresh one per camera segment was 1.5% of the thin
// blob's march). A visit may trace a path that marches again: a nested call takes the next slot.
class MarchScratch {
public:
    MarchScratch();
    ~MarchScratch();
    MarchScratch(const MarchScratch&) = delete;
    MarchScratch& operator=(const MarchScratch&) = delete;
    OpticalDepthProfile& profile;
    std::vector<double>& ts;

    struct Slot {
        OpticalDepthProfile profile;
        std::vector<double> ts;
    };

private:
    explicit MarchScratch(Slot& slot);
    static Slot& take();
};

// The march's points on every medium the segment crosses, in the order above: per point, the other
// media's transmittance from the previous point (a product of independent ratio-tracking
// estimates), `tracked` += per_point, and, while that product is non-zero,
// visit(medium, t, others, m) with the point's weight others x m.mass / m.divisor (times the albedo),
// m from place_counted_march_points. The march gather and the beam gather's single scattering share it.
// With `depth`, adds every medium's optical depth over (0, t_end) to *depth in the scene's order, as
// transport/seen_through.h's exact_transmittance sums it (from the profiles the points were placed on:
// the segment is not walked twice where a light is seen behind it). With `masses` (one per medium, in
// the scene's order), sets each medium's m ({0, 1} where it places no points).
template <class Visit>
void for_each_march_point(const Scene& scene, const Ray& ray, double t_end, int n, MarchCount count, Rng& rng,
                          uint64_t per_point, uint64_t& tracked, Visit&& visit, double* depth = nullptr,
                          MarchMass* masses = nullptr) {
    MarchScratch scratch;
    OpticalDepthProfile& profile = scratch.profile;
    std::vector<double>& ts = scratch.ts;
    for (size_t index = 0; index < scene.media.size(); ++index) {
        const auto& medium = scene.media[index];
        if (masses) masses[index] = MarchMass{};
        if ((medium->albedo() == 0.0).all()) {
            if (depth) {
                medium->optical_depth_profile(ray, t_end, profile);
                if (!profile.empty()) *depth += profile.total();
            }
            continue;
        }
        const MarchMass mass = place_counted_march_points(*medium, ray, t_end, n, count, rng, profile, ts);
        if (masses) masses[index] = mass;
        if (depth && !profile.empty()) *depth += profile.total();
        double others = 1.0, t_prev = 0.0;   // the other media's transmittance to the point
        for (const double t : ts) {
            for (const auto& m : scene.media)
                if (m != medium) others *= m->transmittance(Ray{ray.at(t_prev), ray.dir}, t - t_prev, rng);
            tracked += per_point;
            t_prev = t;
            if (others == 0.0) break;
            visit(*medium, t, others, mass);
        }
    }
}

}  // namespace vpm
