#include "analysis/metrics/seen_lights.h"

#include <cmath>
#include <limits>

#include <tbb/parallel_for.h>

#include "core/error.h"
#include "scene/materials/material.h"
#include "transport/walk_steps.h"

namespace vpm {

namespace {

// Whether `ray` reaches an area light, through at most `depth` more specular events.
bool reaches_light(const Scene& scene, const Ray& ray, int depth) {
    SurfaceHit hit;
    if (!scene.intersect(ray, kInfinity, hit)) return false;
    if (hit.emitter) return true;
    if (!hit.specular || depth == 0) return false;
    // Both events of a dielectric (u1 below and above its Fresnel reflectance), the one of a mirror.
    Vec3 previous = Vec3::Zero();
    for (const double u1 : {0.0, std::nextafter(1.0, 0.0)}) {
        MaterialSample s;
        if (!hit.specular->sample(ray.dir, hit.normal, hit.exiting, Transport::radiance, u1, 0.0, 0.0, s)) continue;
        if (s.dir == previous) continue;   // total internal reflection, or a mirror: one direction
        previous = s.dir;
        if (reaches_light(scene, spawn_ray(hit, s.dir), depth - 1)) return true;
    }
    return false;
}

}  // namespace

std::vector<uint8_t> seen_light_pixels(const Scene& scene, int width, int height, int side) {
    const Camera& camera = scene.camera;
    // The same aspect ratio within rounding of a pixel on either side.
    const double scale_x = double(camera.width()) / double(width), scale_y = double(camera.height()) / double(height);
    if (width <= 0 || height <= 0 || std::abs(scale_x - scale_y) > std::max(scale_x, scale_y) / double(std::min(width, height)))
        throw Error("the images are " + std::to_string(width) + "x" + std::to_string(height) + ", the scene's camera " +
                    std::to_string(camera.width()) + "x" + std::to_string(camera.height()) +
                    ": a light mask needs the same aspect ratio (set render.width and render.height as the images were rendered)");
    std::vector<uint8_t> seen(size_t(width) * size_t(height), 0);
    if (scene.area_lights().empty()) return seen;
    tbb::parallel_for(0, height, [&](int y) {
        for (int x = 0; x < width; ++x) {
            bool any = false;
            for (int j = 0; j < side * side && !any; ++j) {
                const double u = (double(j % side) + 0.5) / double(side), v = (double(j / side) + 0.5) / double(side);
                any = reaches_light(scene, camera.generate_ray((double(x) + u) * scale_x, (double(y) + v) * scale_y),
                                    kSeenLightSpecularDepth);
            }
            seen[size_t(y) * size_t(width) + size_t(x)] = any ? 1 : 0;
        }
    });
    return seen;
}

void exclude_seen_lights(PixelMask& mask, const Scene& scene, const std::string& name) {
    mask.exclude_marked(seen_light_pixels(scene, mask.width(), mask.height()), "exclude lights seen in " + name);
}

}  // namespace vpm
