#include "render/segment_direct_light.h"

#include <vector>

#include "scene/media/optical_depth_profile.h"
#include "transport/direct_light.h"
#include "transport/march_points.h"

namespace vpm {

Rgb segment_direct_light(const Scene& scene, const Ray& ray, double t_end, int n, Rng& rng, uint64_t& rays) {
    OpticalDepthProfile profile;
    std::vector<double> ts;
    Rgb sum = Rgb::Zero();
    for (const auto& medium : scene.media) {
        if ((medium->albedo() == 0.0).all()) continue;
        const double mass = place_march_points(*medium, ray, t_end, n, rng, profile, ts);
        double others = 1.0, t_prev = 0.0;   // the other media's transmittance to the point
        for (const double t : ts) {
            for (const auto& m : scene.media)
                if (m != medium) others *= m->transmittance(Ray{ray.at(t_prev), ray.dir}, t - t_prev, rng);
            rays += scene.media.size() + 1;   // the profile or the other media, and the shadow ray
            t_prev = t;
            if (others == 0.0) break;
            sum += (others * mass / n) * medium->albedo() * direct_light_in_medium(scene, ray.at(t), ray.dir, medium->g(), rng);
        }
    }
    return sum;
}

}  // namespace vpm
