#include "analysis/metrics/reference_samples.h"

#include <fstream>

#include <nlohmann/json.hpp>

#include "render/run/run_record.h"

namespace vpm {

std::optional<uint64_t> recorded_samples(const std::filesystem::path& exr) {
    std::ifstream in(sidecar_path_for(exr));
    if (!in) return std::nullopt;
    const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
    if (j.is_discarded() || !j.is_object() || !j.contains("render") || !j["render"].is_object()) return std::nullopt;
    const nlohmann::json& r = j["render"];
    if (!r.contains("samples") || !r["samples"].is_number_unsigned()) return std::nullopt;
    return r["samples"].get<uint64_t>();
}

std::string more_samples_warning(const std::string& run, uint64_t run_samples, const std::string& reference,
                                 uint64_t reference_samples) {
    if (run_samples <= reference_samples) return "";
    return "warning: " + run + " took " + std::to_string(run_samples) + " camera samples, more than the " +
           std::to_string(reference_samples) + " of its reference " + reference +
           ": its error is then mostly the reference's own noise (render the reference with many more samples)";
}

}  // namespace vpm
