#pragma once
// The JSON sidecar every run writes beside its output ("out.exr" -> "out.json"): phase timings,
// peak memory, environment and the resolved config. The header sees only nlohmann/json_fwd.hpp
// (pimpl); code that wants to pass or edit arbitrary JSON includes <nlohmann/json.hpp> itself.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <type_traits>
#include <vector>

#include <nlohmann/json_fwd.hpp>

namespace vpm {

class RunRecord {
public:
    RunRecord();
    ~RunRecord();
    RunRecord(const RunRecord& other);
    RunRecord& operator=(const RunRecord& other);
    RunRecord(RunRecord&&) noexcept;
    RunRecord& operator=(RunRecord&&) noexcept;

    // A record with the standard fields: "git_revision" (git_revision()), "vpm_version",
    // "hostname", "threads" (the tbb::global_control thread limit in force unless `threads` > 0),
    // "physical_memory_bytes", "date_utc" (ISO-8601, e.g. "2026-11-22T01:17:20Z") and, when
    // argv is given, "command_line" (array of strings).
    static RunRecord with_environment(int argc = 0, const char* const* argv = nullptr, int threads = 0);

    // Sets a value at a dotted path ("phases.trace.seconds"), creating objects on the way and
    // replacing whatever was there.
    void set(const std::string& path, const nlohmann::json& value);
    void set(const std::string& path, const std::string& value);
    void set(const std::string& path, const char* value);
    void set(const std::string& path, const std::vector<std::string>& value);
    template <class T, std::enable_if_t<std::is_arithmetic_v<T>, int> = 0>
    void set(const std::string& path, T value) {
        if constexpr (std::is_same_v<T, bool>) set_bool(path, value);
        else if constexpr (std::is_integral_v<T> && std::is_signed_v<T>) set_int(path, int64_t(value));
        else if constexpr (std::is_integral_v<T>) set_uint(path, uint64_t(value));
        else set_double(path, double(value));
    }

    // Records phases.<name>.seconds and phases.<name>.peak_rss_bytes (peak so far, at the call).
    void phase(const std::string& name, double seconds);

    // Sets "peak_rss_bytes" to the process peak now, then writes the JSON (2-space indent)
    // atomically with write_text_atomic. Throws FileError.
    void write(const std::filesystem::path& path);

    std::string dump(int indent = 2) const;
    nlohmann::json& json();
    const nlohmann::json& json() const;

private:
    void set_bool(const std::string& path, bool v);
    void set_int(const std::string& path, int64_t v);
    void set_uint(const std::string& path, uint64_t v);
    void set_double(const std::string& path, double v);

    struct Impl;
    std::unique_ptr<Impl> impl_;
};

// "dir/out.exr" -> "dir/out.json" and "dir/out.png" (extension replaced, or added if none).
std::filesystem::path sidecar_path_for(const std::filesystem::path& output);
std::filesystem::path preview_path_for(const std::filesystem::path& output);

}  // namespace vpm
