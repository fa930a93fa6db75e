#include "analysis/sweep/row_hash.h"

#include <cstdio>
#include <fstream>
#include <sstream>

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

std::string file_content_key(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return path;   // unreadable: the path is all there is (the scene could not load anyway)
    std::ostringstream bytes;
    bytes << in.rdbuf();
    const std::string b = bytes.str();
    return "content " + hash_hex(b) + " size " + std::to_string(b.size());
}

std::string scene_hash(const toml::table& resolved) {
    toml::table t = resolved;
    // Files by content, not by where the checkout lives: a resolved path is absolute, so hashing it
    // made every worktree render its own references of the same scene.
    for (const char* array : {"media", "lights", "shapes"})
        if (auto* a = t.get_as<toml::array>(array))
            for (auto& e : *a)
                if (auto* entry = e.as_table())
                    if (auto file = entry->get_as<std::string>("file")) entry->insert_or_assign("file", file_content_key(file->get()));
    return hash_hex(to_toml_string(without(
        t, {"output", "threads", "integrator", "spp", "seed", "max_depth", "rr_depth", "mis", "exposure", "passes",
                   "time_limit", "first_pass"},
        true)));
}

}  // namespace vpm
