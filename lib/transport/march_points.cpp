#include "transport/march_points.h"

#include <cmath>

namespace vpm {

double place_march_points(const Medium& medium, const Ray& ray, double tmax, int n, Rng& rng,
                          OpticalDepthProfile& profile, std::vector<double>& ts) {
    ts.clear();
    medium.optical_depth_profile(ray, tmax, profile);
    const double total = profile.total();
    if (profile.empty() || !(total > 0.0) || n <= 0) return 0.0;
    // A profile cut at kEnoughDepth gives the same P as the whole one: both round to 1.
    const double mass = -std::expm1(-total);
    size_t cursor = 0;
    for (int j = 0; j < n; ++j) {
        // Stratum j of the mass; increasing in j, and below 37 since the fraction is < 1 in double.
        const double tau = -std::log1p(-mass * (j + rng.uniform()) / n);
        ts.push_back(profile.invert(tau, cursor));
    }
    return mass;
}

}  // namespace vpm
