#pragma once
// Pass sets rendered apart (other machines, Slurm array tasks) combined into one image. Each
// input is an EXR with its JSON sidecar; run i holds passes first_i .. first_i + count_i - 1 of the
// same config, so the mean weighted by pass counts is exactly the image one machine would have
// rendered with all the passes (up to float rounding of the stored images).
//
// Refused with one clear error naming the file: a missing or unreadable sidecar, a different
// scene or setting (hash of the resolved config without render.output, threads, passes,
// first_pass, spp, time_limit and exposure), a different number of samples per pass or image
// size, or pass ranges that overlap (the same pass twice would not be independent). Sidecars are
// validated like configs: passes.first (0 .. INT_MAX, default 0), passes.count (1 .. INT_MAX, first + count - 1
// <= INT_MAX), passes.spp_per_pass (1 .. 2^24) must be integers in range, config an object and
// config.render.exposure a number in [-64, 64]; anything else is one error naming the file and key.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "render/run/image.h"
#include <nlohmann/json_fwd.hpp>

#include "render/run/run_record.h"

namespace vpm {

struct MergedRun {
    Image image;
    RunRecord record;   // the first input's record with the merged pass counts and the inputs
    int64_t passes = 0;   // non-overlapping ranges of indices <= INT_MAX: no overflow
    double exposure = 0.0;
};

MergedRun merge_runs(const std::vector<std::filesystem::path>& inputs);

// The hash two runs must share to be merged (see above), from a sidecar's "config".
std::string merge_identity(const nlohmann::json& config);

}  // namespace vpm
