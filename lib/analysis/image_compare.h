#pragma once
// Error of an image against a reference of the same size (all pixels, all three channels).
//
//   rmse          sqrt(mean (a - r)^2)
//   relative_rmse rmse / mean(r)            (0 when mean(r) is 0)
//   relative_bias mean(a) / mean(r) - 1     (overall brightness error, e.g. the estimator bias)
#include <string>

#include "render/image.h"

namespace vpm {

struct ImageError {
    double rmse = 0.0;
    double relative_rmse = 0.0;
    double relative_bias = 0.0;
    double mean = 0.0;            // mean of the image
    double reference_mean = 0.0;  // mean of the reference
    size_t nonfinite = 0;         // non-finite values in either image (left out of all sums)
};

// Throws vpm::Error when the sizes differ.
ImageError compare_images(const Image& image, const Image& reference);

}  // namespace vpm
