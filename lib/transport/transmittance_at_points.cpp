#include "transport/transmittance_at_points.h"

#include <cmath>

#include "scene/media/homogeneous_medium.h"

namespace vpm {

std::vector<bool> homogeneous_media(const Scene& scene) {
    std::vector<bool> exact;
    for (const auto& m : scene.media) exact.push_back(dynamic_cast<const HomogeneousMedium*>(m.get()) != nullptr);
    return exact;
}

void transmittance_at_points(const Scene& scene, const std::vector<bool>& exact, const Ray& ray, const double* ts,
                             size_t n, double* out, Rng& rng, uint64_t& lookups) {
    for (size_t i = 0; i < n; ++i) out[i] = 1.0;
    if (n == 0) return;
    const double t_last = ts[n - 1];
    for (size_t mi = 0; mi < scene.media.size(); ++mi) {
        const Medium& m = *scene.media[mi];
        const bool closed_form = exact[mi];
        size_t i = 0;
        double acc = closed_form ? 0.0 : 1.0;   // optical depth so far, or the ratio-tracking product
        m.majorant_pieces(ray, t_last, [&](double ta, double tb, double mu) {
            if (closed_form) {
                const double before = std::exp(-acc);
                for (; i < n && ts[i] <= ta; ++i) out[i] *= before;
                for (; i < n && ts[i] <= tb; ++i) out[i] *= std::exp(-(acc + mu * (ts[i] - ta)));
                acc += mu * (tb - ta);
                return true;
            }
            double t = ta;
            while (mu > 0.0) {
                t += -std::log1p(-rng.uniform()) / mu;
                const double stop = std::min(t, tb);
                for (; i < n && ts[i] < stop; ++i) out[i] *= acc;
                if (t >= tb) break;
                acc *= 1.0 - m.sigma_t(ray.at(t)) / mu;
                ++lookups;
            }
            for (; i < n && ts[i] <= tb; ++i) out[i] *= acc;
            return acc != 0.0;
        });
        const double rest = closed_form ? std::exp(-acc) : acc;
        for (; i < n; ++i) out[i] *= rest;
    }
}

}  // namespace vpm
