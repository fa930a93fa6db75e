#include "photon/trace/forced_collision.h"

#include <cmath>

namespace vpm {

bool forced_collisions_possible(const Scene& scene) { return scene.media.size() == 1; }

ForcedStep forced_step(const Scene& scene, const Ray& ray, Rng& rng, OpticalDepthProfile& scratch) {
    ForcedStep out;
    PathVertex& v = out.vertex;
    v.on_surface = scene.intersect(ray, kInfinity, v.hit);
    if (v.on_surface && ((v.hit.reflectance > 0.0).any() || v.hit.specular)) {   // the analog step, without a second intersect
        v.medium = scene.sample_medium(ray, v.hit.t, rng);
        out.forced = false;
        return out;
    }
    const Medium& medium = *scene.media.front();
    medium.optical_depth_profile(ray, v.on_surface ? v.hit.t : kInfinity, scratch);
    const double tau = scratch.empty() ? 0.0 : scratch.total();
    if (!(tau > 0.0)) return out;   // nothing to collide with: the photon passes, as the analog walk would
    const double u = rng.uniform();
    double depth;
    if (tau > kForcedMaxDepth) {   // thick: the analog free flight, exact from the same profile
        depth = -std::log1p(-u);
        out.transmittance = 0.0;   // no weighting: the collision (or the pass) is the analog outcome
        if (!(depth < tau)) return out;   // passes the segment: out of the medium, onto the black surface
    } else {
        // 1 - exp(-tau) without cancellation for thin segments.
        const double collide = -std::expm1(-tau);
        out.transmittance = 1.0 - collide;
        // tau* from the density exp(-tau*) on [0, tau), normalised by 1 - exp(-tau); below tau always.
        depth = std::min(-std::log1p(-u * collide), std::nextafter(tau, 0.0));
    }
    size_t cursor = 0;
    v.medium.t = scratch.invert(depth, cursor);
    v.medium.medium = &medium;
    return out;
}

}  // namespace vpm
