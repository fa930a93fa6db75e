#pragma once
// Shared helpers for the benchmarks in bench/ (header only: every bench/*.cpp is its own program).
#include <filesystem>
#include <string>

namespace vpm::bench {

// configs/NAME in the source tree. __FILE__ is either absolute or relative to the build folder
// (Ninja inside the source tree), which is where the benchmark executables live.
inline std::string config_path(const char* name) {
    std::filesystem::path src = std::filesystem::path(__FILE__).parent_path().parent_path();
    if (src.is_relative()) src = std::filesystem::canonical("/proc/self/exe").parent_path() / src;
    return (src / "configs" / name).lexically_normal().string();
}

}  // namespace vpm::bench
