#pragma once
// A reference's own noise, per pixel, so error metrics can subtract it (error_metrics.h's floor).
// Two sources:
//   - the variance image a render writes beside its EXR (`vpm render --variance`: OUT.variance.exr,
//     the variance of each pixel's luminance estimate from the spread of its independent passes;
//     render/run/run.h, RunOptions::pass_variance), found beside a reference automatically;
//   - a reference given as two halves A and B rendered on independent streams: the reference is
//     (A + B) / 2 and its variance per pixel ((Y_A - Y_B) / 2)^2, unbiased when A and B have equal variance.
// Variance images are grey: the luminance variance in all three channels.
#include <filesystem>
#include <optional>
#include <string>

#include "render/run/image.h"

namespace vpm {

// OUT.exr -> OUT.variance.exr.
std::filesystem::path variance_path_for(const std::filesystem::path& exr);

struct NoisyReference {
    Image image;
    std::optional<Image> variance;   // per-pixel luminance variance; none: unknown
    std::string name;                // the file, or "A + B" for halves
    std::string noise_source;        // where the variance came from ("" when unknown)
};

// REFERENCE.exr, with REFERENCE.variance.exr when it exists beside it (or `variance_file` when not
// empty, which must exist). Throws vpm::Error naming a file whose size differs.
NoisyReference load_reference(const std::filesystem::path& exr, const std::filesystem::path& variance_file = {});

// The reference as the mean of two halves, and its variance from their difference. Throws vpm::Error
// when sizes differ.
NoisyReference reference_from_halves(const Image& a, const Image& b, const std::string& name);
NoisyReference load_reference_halves(const std::filesystem::path& a, const std::filesystem::path& b);

}  // namespace vpm
