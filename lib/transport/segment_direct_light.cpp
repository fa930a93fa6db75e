#include "transport/segment_direct_light.h"

#include "transport/direct_light.h"
#include "transport/march_points.h"

namespace vpm {

Rgb segment_direct_light(const Scene& scene, const Ray& ray, double t_end, int n, Rng& rng, uint64_t& rays) {
    Rgb sum = Rgb::Zero();
    // Per point: the profile or the other media, and the shadow ray.
    for_each_march_point(scene, ray, t_end, n, MarchCount::fixed, rng, scene.media.size() + 1, rays,
                         [&](const Medium& medium, double t, double others, MarchMass mass) {
                             sum += (others * mass.mass / mass.divisor) * medium.albedo() *
                                    direct_light_in_medium(scene, ray.at(t), ray.dir, medium.g(), rng);
                         });
    return sum;
}

}  // namespace vpm
