#include "transport/segment_direct_light.h"

#include <optional>
#include <vector>

#include "transport/direct_light.h"
#include "transport/equiangular.h"
#include "transport/march_points.h"

namespace vpm {

Rgb segment_direct_light(const Scene& scene, const Ray& ray, double t_end, int n, Rng& rng, uint64_t& rays,
                         bool equiangular) {
    Rgb sum = Rgb::Zero();
    std::optional<EquiangularSegment> segment;
    if (equiangular) {
        segment.emplace(scene, ray, t_end);
        if (segment->empty()) segment.reset();
    }
    if (!segment) {
        // Per point: the profile or the other media, and the shadow ray.
        for_each_march_point(scene, ray, t_end, n, MarchCount::fixed, rng, scene.media.size() + 1, rays,
                             [&](const Medium& medium, double t, double others, MarchMass mass) {
                                 sum += (others * mass.mass / mass.divisor) * medium.albedo() *
                                        direct_light_in_medium(scene, ray.at(t), ray.dir, medium.g(), rng);
                             });
        return sum;
    }
    thread_local std::vector<MarchMass> masses;
    masses.assign(scene.media.size(), MarchMass{});
    for_each_march_point(
        scene, ray, t_end, n, MarchCount::fixed, rng, scene.media.size() + 1, rays,
        [&](const Medium& medium, double t, double others, MarchMass mass) {
            const Vec3 x = ray.at(t);
            const size_t i = segment->medium_index(medium);
            const SegmentPoint at{&*segment, t, march_density(mass, medium.sigma_t(x), segment->medium_depth(i, t))};
            sum += (others * mass.mass / mass.divisor) * medium.albedo() *
                   direct_light_in_medium(scene, x, ray.dir, medium.g(), rng, false, &at);
        },
        nullptr, masses.data());
    return sum + segment->in_scattering(rng, rays, [&](size_t i, double sigma_t, double tau_m, double) {
               return march_density(masses[i], sigma_t, tau_m);
           });
}

}  // namespace vpm
