#include "transport/seen_through.h"

#include <cmath>

namespace vpm {

double exact_transmittance(const Scene& scene, const Ray& ray, double t_end, OpticalDepthProfile& profile) {
    double depth = 0.0;
    for (const auto& medium : scene.media) {
        medium->optical_depth_profile(ray, t_end, profile);
        if (!profile.empty()) depth += profile.total();
    }
    return std::exp(-depth);
}

Rgb seen_through(const Scene& scene, const Ray& ray, bool on_surface, const SurfaceHit& hit, const EmissionWeighting& emission,
                 OpticalDepthProfile& profile, uint64_t& rays) {
    const Rgb e = on_surface ? emitted_radiance(scene, ray, hit, emission) : escaped_radiance(scene, ray.dir, emission);
    if ((e == 0.0).all()) return e;
    ++rays;
    return e * exact_transmittance(scene, ray, on_surface ? hit.t : kInfinity, profile);
}

Rgb seen_through_depth(const Scene& scene, const Ray& ray, bool on_surface, const SurfaceHit& hit,
                       const EmissionWeighting& emission, double depth, uint64_t& rays) {
    const Rgb e = on_surface ? emitted_radiance(scene, ray, hit, emission) : escaped_radiance(scene, ray.dir, emission);
    if ((e == 0.0).all()) return e;
    ++rays;
    return e * std::exp(-depth);
}

}  // namespace vpm
