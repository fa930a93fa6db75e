// libFuzzer target: a scene config from arbitrary text (parse_config + Scene::build).
// Any vpm::Error is a valid outcome (a user error with a message); everything else (a crash, a
// sanitizer report, another exception type, a hang) is a bug.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>

#include "core/error.h"
#include "config/params.h"
#include "render/run/run_config.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    try {
        // base_dir: an empty folder, so file references fail cleanly instead of reading the host.
        static const std::filesystem::path dir = [] {
            auto d = std::filesystem::temp_directory_path() / "vpm_fuzz_config_empty";
            std::filesystem::create_directories(d);
            return d;
        }();
        auto doc = vpm::parse_config(text, "fuzz.toml", dir);
        const vpm::RunConfig config = vpm::RunConfig::build(doc);
        (void)config.resolved_toml();
    } catch (const vpm::Error&) {
    }
    return 0;
}
