#include "scene/materials/fresnel.h"

#include <algorithm>
#include <cmath>

namespace vpm {

double fresnel_dielectric(double cos_i, double eta, double& cos_t) {
    cos_i = std::clamp(cos_i, 0.0, 1.0);
    const double sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
    if (sin2_t >= 1.0) {
        cos_t = 0.0;
        return 1.0;
    }
    cos_t = std::sqrt(1.0 - sin2_t);
    // Amplitude ratios for the field perpendicular (s) and parallel (p) to the plane of incidence.
    const double rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    const double rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    return 0.5 * (rs * rs + rp * rp);
}

}  // namespace vpm
