#include "scene/camera_region.h"

#include "core/sampling/rng.h"
#include "scene/scene.h"

namespace vpm {

Bounds3 camera_seen_region(const Scene& scene) {
    Bounds3 points;
    Rng rng(0x63616d657261ULL, 0x726567696f6eULL);   // "camera", "region": the same box on every run
    const int w = scene.camera.width(), h = scene.camera.height();
    for (int i = 0; i < kCameraRegionRays; ++i) {
        const Ray ray = scene.camera.generate_ray(rng.uniform() * w, rng.uniform() * h);
        SurfaceHit hit;
        const double t_surface = scene.intersect(ray, kInfinity, hit) ? hit.t : kInfinity;
        const MediumEvent event = scene.sample_medium(ray, t_surface, rng);
        if (event) points.extend(ray.at(event.t));
        else if (t_surface < kInfinity) points.extend(ray.at(t_surface));
    }
    if (points.empty()) return points;
    const Vec3 grow = Vec3::Constant(kCameraRegionMargin * (points.hi - points.lo).norm());
    points.lo -= grow;
    points.hi += grow;
    return points;
}

}  // namespace vpm
