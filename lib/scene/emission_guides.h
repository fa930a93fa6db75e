#pragma once
// Photon emission guided by what each direction reaches. A point light, or a sphere light near the
// media, emits over wide directions; where the medium's mass sits in a small part of them (smoke
// whose grid box is far larger than its puff, a light beside a small dense cloud), nearly every
// photon leaves through empty or thin space and nothing is stored: in a third-party smoke lit by
// a sphere light beside it, 428 of 1e5 photons collided at all (docs/studies/heldout_scenes.md section 23, h6),
// and the map of 2061 photons set the image's error.
//
// For such a light a DirectionGuide (scene/lights/direction_guide.h) is built from rays traced from
// the light's centre through its cells (kGuideRaysPerSide^2 jittered rays per cell): a direction's
// weight is the light's own density there times the probability that a photon leaving that way
// reaches something at first flight, 1 - exp(-optical depth) through the media, or 1 where it meets
// a surface. The light then draws kGuideShare of its photons from the guide and the rest as before,
// each weighted by the mixture's density (one-sample MIS): the map stays unbiased, and a direction
// the guide misses is still sampled by the light's own emission, with at most 1 / (1 - kGuideShare)
// its usual weight. A light is guided only where the mixture is expected to make at least
// kGuideMinGain times as many photons reach something: elsewhere (a box lit from outside, a light
// inside a dense medium) its photons are exactly as before. Deterministic (fixed rays, its own
// seed) and scale-invariant (optical depths and directions only).
#include <string>
#include <vector>

namespace vpm {

class Scene;

constexpr double kGuideShare = 0.5;
constexpr double kGuideMinGain = 2.0;
constexpr int kGuideRaysPerSide = 2;

// What the guide rays found for one light: the fraction of its own photons expected to reach
// something at first flight, and of the mixture's (equal when unguided).
struct EmissionGuideEstimate {
    bool guided = false;
    double reach_own = 0.0;
    double reach_mixture = 0.0;
};

// Builds and sets the guides of the scene's lights that take one (Light::guide_origin); one log
// line per guided light. Called once, before the first photon is traced (Scene::prepare_photon_emission).
std::vector<std::string> guide_photon_emission(const Scene& scene);

// The estimate for one light from its origin (exposed for tests); `guide` receives its weights.
EmissionGuideEstimate estimate_emission_guide(const Scene& scene, size_t light, std::vector<double>& weights);

}  // namespace vpm
