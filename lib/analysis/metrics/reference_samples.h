#pragma once
// A run against a reference with fewer camera samples than the run: its error is then mostly the
// reference's own noise, not the run's. Sweeps, `vpm compare`, `vpm bench equal-time`, `vpm render
// --reference` and vpm.compare warn with these.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

namespace vpm {

// render.samples of the sidecar beside an EXR (OUT.exr -> OUT.json); nullopt when there is no
// sidecar or it has no such count (an EXR from elsewhere).
std::optional<uint64_t> recorded_samples(const std::filesystem::path& exr);

// "warning: RUN took N camera samples, more than the M of its reference REFERENCE: ..." or "" when
// run_samples <= reference_samples.
std::string more_samples_warning(const std::string& run, uint64_t run_samples, const std::string& reference,
                                 uint64_t reference_samples);

}  // namespace vpm
