#include "analysis/row_hash.h"

#include <cstdio>

#include "config/params.h"

namespace vpm {

std::string hash_hex(const std::string& bytes) {
    uint64_t h = 14695981039346656037ull;
    for (unsigned char c : bytes) {
        h ^= c;
        h *= 1099511628211ull;
    }
    char buf[17];
    std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
    return buf;
}

namespace {

toml::table without(const toml::table& resolved, std::initializer_list<const char*> render_keys, bool drop_photons) {
    toml::table t = resolved;
    if (auto* r = t.get_as<toml::table>("render"))
        for (const char* k : render_keys) r->erase(k);
    if (drop_photons) t.erase("photons");
    return t;
}

}  // namespace

std::string run_config_text(const toml::table& resolved) {
    return to_toml_string(without(resolved, {"output", "threads"}, false));
}

std::string run_hash(const toml::table& resolved, uint64_t seed, uint64_t stream_offset) {
    return hash_hex(run_config_text(resolved) + "\nseed=" + std::to_string(seed) +
                    "\nstream_offset=" + std::to_string(stream_offset) + "\n");
}

std::string scene_hash(const toml::table& resolved) {
    return hash_hex(to_toml_string(without(
        resolved, {"output", "threads", "integrator", "spp", "seed", "max_depth", "rr_depth", "mis", "exposure", "passes",
                   "time_limit", "first_pass"},
        true)));
}

}  // namespace vpm
