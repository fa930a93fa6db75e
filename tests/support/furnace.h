#pragma once
// The uniform furnace (configs/uniform_furnace.toml: the camera at the centre of a non-absorbing
// sphere under a constant sky, radiance L everywhere): the share of its image that a density
// estimate makes, for the tests that check an estimator's known bias in the image.
#include <cmath>
#include <limits>

#include "render/run/run_config.h"

namespace vpm::test {

// Camera rays that leave the sphere without a collision see the sky itself: exp(-tau) of the image,
// tau the sphere's optical radius (the same in every direction from the centre). The rest is
// estimated, so estimates (1 + b) L make an image of mean (1 + (1 - exp(-tau)) b) L, and the
// paired ratio classic / corrected is 1 + (1 - exp(-tau)) / (k - 1) rather than k / (k - 1).
inline double furnace_estimated_share(const RunConfig& config) {
    const Ray centre = config.scene->camera.generate_ray(0.5 * config.render.width, 0.5 * config.render.height);
    return 1.0 - std::exp(-config.scene->optical_depth(centre, std::numeric_limits<double>::infinity()));
}

// The furnace image's expected mean over L for an estimator of relative bias `estimate_bias`.
inline double furnace_image_over_truth(const RunConfig& config, double estimate_bias) {
    return 1.0 + furnace_estimated_share(config) * estimate_bias;
}

}  // namespace vpm::test
