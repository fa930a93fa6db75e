#include "core/build_info.h"
#include "render/run/run_record.h"

#include <tbb/global_control.h>
#include <tbb/info.h>
#include <unistd.h>

#include <climits>
#include <cmath>
#include <ctime>
#include <nlohmann/json.hpp>

#include "core/progress.h"
#include "render/run/image_io.h"

namespace vpm {

struct RunRecord::Impl {
    nlohmann::json j = nlohmann::json::object();

    nlohmann::json& at_path(const std::string& path) {
        nlohmann::json* node = &j;
        size_t start = 0;
        while (true) {
            const size_t dot = path.find('.', start);
            const std::string key = path.substr(start, dot == std::string::npos ? std::string::npos : dot - start);
            if (!node->is_object()) *node = nlohmann::json::object();
            node = &(*node)[key];
            if (dot == std::string::npos) return *node;
            start = dot + 1;
        }
    }
};

RunRecord::RunRecord() : impl_(std::make_unique<Impl>()) {}
RunRecord::~RunRecord() = default;
RunRecord::RunRecord(const RunRecord& other) : impl_(std::make_unique<Impl>(*other.impl_)) {}
RunRecord& RunRecord::operator=(const RunRecord& other) {
    if (this != &other) impl_ = std::make_unique<Impl>(*other.impl_);
    return *this;
}
RunRecord::RunRecord(RunRecord&&) noexcept = default;
RunRecord& RunRecord::operator=(RunRecord&&) noexcept = default;

RunRecord RunRecord::with_environment(int argc, const char* const* argv, int threads) {
    RunRecord r;
    r.set("git_revision", git_revision());
    r.set("vpm_version", vpm_version());

    char host[HOST_NAME_MAX + 1] = {};
    if (::gethostname(host, sizeof(host) - 1) != 0) host[0] = '\0';
    r.set("hostname", host[0] ? std::string(host) : std::string("unknown"));

    // The limit in force (--threads sets a tbb::global_control), not the machine's core count.
    r.set("threads", threads > 0 ? threads
                                 : int(tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism)));
    r.set("physical_memory_bytes", physical_memory_bytes());

    const std::time_t now = std::time(nullptr);
    std::tm utc{};
    gmtime_r(&now, &utc);
    char date[32];
    std::strftime(date, sizeof(date), "%Y-%m-%dT%H:%M:%SZ", &utc);
    r.set("date_utc", std::string(date));

    if (argv && argc > 0) {
        std::vector<std::string> args;
        for (int i = 0; i < argc; ++i) args.emplace_back(argv[i] ? argv[i] : "");
        r.set("command_line", args);
    }
    return r;
}

void RunRecord::set(const std::string& path, const nlohmann::json& value) { impl_->at_path(path) = value; }
void RunRecord::set(const std::string& path, const std::string& value) { impl_->at_path(path) = value; }
void RunRecord::set(const std::string& path, const char* value) {
    impl_->at_path(path) = value ? nlohmann::json(value) : nlohmann::json(nullptr);
}
void RunRecord::set(const std::string& path, const std::vector<std::string>& value) {
    impl_->at_path(path) = value;
}
void RunRecord::set_bool(const std::string& path, bool v) { impl_->at_path(path) = v; }
void RunRecord::set_int(const std::string& path, int64_t v) { impl_->at_path(path) = v; }
void RunRecord::set_uint(const std::string& path, uint64_t v) { impl_->at_path(path) = v; }
void RunRecord::set_double(const std::string& path, double v) {
    // JSON has no NaN/Inf; nlohmann would write null silently. Keep it visible instead.
    if (std::isfinite(v)) impl_->at_path(path) = v;
    else impl_->at_path(path) = std::isnan(v) ? "nan" : (v > 0 ? "inf" : "-inf");
}

void RunRecord::phase(const std::string& name, double seconds) {
    nlohmann::json& p = impl_->j["phases"][name];
    p["seconds"] = seconds;
    p["peak_rss_bytes"] = peak_rss_bytes();
}

void RunRecord::write(const std::filesystem::path& path) {
    impl_->j["peak_rss_bytes"] = peak_rss_bytes();
    write_text_atomic(path, dump(2) + "\n");
}

std::string RunRecord::dump(int indent) const {
    // Replace invalid UTF-8 (e.g. odd bytes in a command line) instead of throwing.
    return impl_->j.dump(indent, ' ', false, nlohmann::json::error_handler_t::replace);
}

nlohmann::json& RunRecord::json() { return impl_->j; }
const nlohmann::json& RunRecord::json() const { return impl_->j; }

namespace {
std::filesystem::path with_extension(const std::filesystem::path& output, const char* ext) {
    std::filesystem::path p = output;
    p.replace_extension(ext);
    return p;
}
}  // namespace

std::filesystem::path sidecar_path_for(const std::filesystem::path& output) {
    return with_extension(output, ".json");
}
std::filesystem::path preview_path_for(const std::filesystem::path& output) {
    return with_extension(output, ".png");
}

}  // namespace vpm
