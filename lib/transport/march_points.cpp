#include "transport/march_points.h"

#include <algorithm>
#include <cmath>
#include <memory>

namespace vpm {

namespace {

// n points stratified in the mass [0, P] of a built profile, P = 1 - exp(-total).
void stratify(const OpticalDepthProfile& profile, double mass, int n, Rng& rng, std::vector<double>& ts) {
    size_t cursor = 0;
    for (int j = 0; j < n; ++j) {
        // Stratum j of the mass; increasing in j, and below 37 since the fraction is < 1 in double.
        const double tau = -std::log1p(-mass * (j + rng.uniform()) / n);
        ts.push_back(profile.invert(tau, cursor));
    }
}

// Builds the profile; returns P, or 0 when the medium is not crossed.
double segment_mass(const Medium& medium, const Ray& ray, double tmax, int n, OpticalDepthProfile& profile,
                    std::vector<double>& ts) {
    ts.clear();
    medium.optical_depth_profile(ray, tmax, profile);
    const double total = profile.total();
    if (profile.empty() || !(total > 0.0) || n <= 0) return 0.0;
    // A profile cut at kEnoughDepth gives the same P as the whole one: both round to 1.
    return -std::expm1(-total);
}

}  // namespace

namespace {
// The thread's slots, and how many of them its active calls hold.
thread_local std::vector<std::unique_ptr<MarchScratch::Slot>> t_slots;
thread_local size_t t_held = 0;
}  // namespace

MarchScratch::Slot& MarchScratch::take() {
    if (t_held == t_slots.size()) t_slots.push_back(std::make_unique<Slot>());
    return *t_slots[t_held++];
}

MarchScratch::MarchScratch(Slot& slot) : profile(slot.profile), ts(slot.ts) {}
MarchScratch::MarchScratch() : MarchScratch(take()) {}
MarchScratch::~MarchScratch() { --t_held; }

double place_march_points(const Medium& medium, const Ray& ray, double tmax, int n, Rng& rng,
                          OpticalDepthProfile& profile, std::vector<double>& ts) {
    const double mass = segment_mass(medium, ray, tmax, n, profile, ts);
    if (mass > 0.0) stratify(profile, mass, n, rng, ts);
    return mass;
}

MarchMass place_counted_march_points(const Medium& medium, const Ray& ray, double tmax, int n, MarchCount count,
                                     Rng& rng, OpticalDepthProfile& profile, std::vector<double>& ts) {
    const double mass = segment_mass(medium, ray, tmax, n, profile, ts);
    if (!(mass > 0.0)) return {0.0, 1};
    switch (count) {
        case MarchCount::fixed: stratify(profile, mass, n, rng, ts); return {mass, n};
        case MarchCount::mass: {
            // ceil(n P) is n for P near 1, where rounding could not push it past n anyway.
            const int m = std::max(1, std::min(n, int(std::ceil(n * mass))));
            stratify(profile, mass, m, rng, ts);
            return {mass, m};
        }
        case MarchCount::free_flight: break;
    }
    // Stratum j of the whole ray's free-flight CDF; its point lies in the segment iff its CDF value
    // is below P (the strata increase, so the first one outside ends the list).
    size_t cursor = 0;
    for (int j = 0; j < n; ++j) {
        const double u = (j + rng.uniform()) / n;
        if (!(u < mass)) break;
        ts.push_back(profile.invert(-std::log1p(-u), cursor));
    }
    return {1.0, n};
}

}  // namespace vpm
