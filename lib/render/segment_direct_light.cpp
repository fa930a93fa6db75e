#include "render/segment_direct_light.h"

#include <cmath>
#include <vector>

#include "transport/direct_light.h"

namespace vpm {

Rgb segment_direct_light(const Scene& scene, const Ray& ray, double t_end, int n, Rng& rng, uint64_t& rays) {
    struct Piece {
        double ta, tb, mu;
    };
    std::vector<Piece> pieces;
    std::vector<double> tau(static_cast<size_t>(n));
    Rgb sum = Rgb::Zero();
    for (const auto& medium : scene.media) {
        if ((medium->albedo() == 0.0).all()) continue;
        pieces.clear();
        double total = 0.0;
        medium->majorant_pieces(ray, t_end, [&](double ta, double tb, double mu) {
            pieces.push_back({ta, tb, mu});
            total += mu * (tb - ta);
            return true;
        });
        if (!(total > 0.0)) continue;
        const double mass = -std::expm1(-total);   // P
        for (int j = 0; j < n; ++j) tau[size_t(j)] = -std::log1p(-mass * (j + rng.uniform()) / n);   // increasing
        size_t j = 0;
        double reached = 0.0, transmittance = 1.0, t_prev = 0.0;   // majorant depth at the piece's start
        for (const Piece& p : pieces) {
            const double end = reached + p.mu * (p.tb - p.ta);
            for (; j < size_t(n) && tau[j] < end; ++j) {
                const double t = std::min(p.tb, p.ta + (tau[j] - reached) / p.mu);
                for (const auto& m : scene.media) transmittance *= m->transmittance(Ray{ray.at(t_prev), ray.dir}, t - t_prev, rng);
                rays += scene.media.size();
                t_prev = t;
                if (transmittance == 0.0) break;
                const Vec3 x = ray.at(t);
                const double sigma_t = medium->sigma_t(x);
                if (!(sigma_t > 0.0)) continue;
                const double relative = transmittance * sigma_t / (p.mu * std::exp(-tau[j]));
                ++rays;
                sum += (relative * mass / n) * medium->albedo() * direct_light_in_medium(scene, x, ray.dir, medium->g(), rng);
            }
            reached = end;
            if (j == size_t(n) || transmittance == 0.0) break;
        }
    }
    return sum;
}

}  // namespace vpm
