#pragma once
// Identities of sweep rows. A run is identified by the hash of its resolved scene config (every
// default filled in, so two spellings of the same config agree) plus its seed and repeat stream;
// a finished row with the same hash is never run again (resume), and merge drops duplicates by it.
// A reference image is cached under the hash of the resolved config minus everything that only
// concerns the estimator, the budget or the output (render.integrator/spp/seed/output/threads/
// max_depth/rr_depth/exposure/passes/time_limit/first_pass and the [photons] table), so every run
// of the same scene shares it.
#include <cstdint>
#include <string>

#include <toml++/toml.h>

namespace vpm {

// 64-bit FNV-1a of the bytes, as 16 lower-case hex digits. Stable across platforms and builds.
std::string hash_hex(const std::string& bytes);

// The resolved config as canonical TOML text without render.output and render.threads (they do
// not change the image).
std::string run_config_text(const toml::table& resolved);
// "content HASH size N" of the file at `path` (the path itself when it cannot be read).
std::string file_content_key(const std::string& path);
// Hash identifying one run: run_config_text + seed + stream offset.
std::string run_hash(const toml::table& resolved, uint64_t seed, uint64_t stream_offset);
// Hash of the scene alone (see above), for the reference cache: without the [render] keys that pick
// how the image is estimated (integrator, samples, seed, passes, budgets, roulette, MIS) rather than
// what it converges to, so one path-traced reference serves every method. A `file` of [[media]],
// [[lights]] or [[shapes]] counts by its content (file_content_key), so checkouts in different
// folders share references.
std::string scene_hash(const toml::table& resolved);

}  // namespace vpm
