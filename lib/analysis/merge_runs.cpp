#include "analysis/merge_runs.h"

#include <algorithm>
#include <fstream>

#include <nlohmann/json.hpp>

#include "analysis/row_hash.h"
#include "core/error.h"
#include "render/image_io.h"

namespace vpm {

namespace {

struct Input {
    std::filesystem::path exr;
    nlohmann::json sidecar;
    Image image;
    int first = 0, count = 0, spp_per_pass = 0;
};

Input read_input(const std::filesystem::path& exr) {
    Input in;
    in.exr = exr;
    const std::filesystem::path json = sidecar_path_for(exr);
    std::ifstream f(json);
    if (!f) throw FileError(json.string() + ": cannot read the sidecar of " + exr.string() + " (vpm merge needs both)");
    in.sidecar = nlohmann::json::parse(f, nullptr, false);
    if (in.sidecar.is_discarded() || !in.sidecar.contains("config") || !in.sidecar.contains("passes"))
        throw FileError(json.string() + ": not a vpm render sidecar with \"config\" and \"passes\"");
    const nlohmann::json& p = in.sidecar["passes"];
    in.first = p.value("first", 0);
    in.count = p.value("count", 0);
    in.spp_per_pass = p.value("spp_per_pass", 0);
    if (in.count < 1 || in.spp_per_pass < 1) throw FileError(json.string() + ": passes.count / spp_per_pass missing or < 1");
    in.image = read_exr(exr);
    return in;
}

}  // namespace

std::string merge_identity(const nlohmann::json& config) {
    nlohmann::json c = config;
    if (c.contains("render") && c["render"].is_object())
        for (const char* k : {"output", "threads", "passes", "first_pass", "spp", "time_limit", "exposure"})
            c["render"].erase(k);
    return hash_hex(c.dump());
}

MergedRun merge_runs(const std::vector<std::filesystem::path>& paths) {
    if (paths.size() < 2) throw Error("merge: give at least two images");
    std::vector<Input> inputs;
    for (const auto& p : paths) inputs.push_back(read_input(p));
    const Input& a = inputs.front();
    const std::string identity = merge_identity(a.sidecar["config"]);
    for (const Input& b : inputs) {
        if (merge_identity(b.sidecar["config"]) != identity)
            throw Error(b.exr.string() + ": rendered from a different scene or setting than " + a.exr.string() +
                        " (resolved configs differ beyond output, threads, passes, first_pass, spp, time_limit, "
                        "exposure); diff their sidecars' \"config\"");
        if (b.spp_per_pass != a.spp_per_pass)
            throw Error(b.exr.string() + ": " + std::to_string(b.spp_per_pass) + " samples per pass, " + a.exr.string() +
                        " has " + std::to_string(a.spp_per_pass) + "; passes of different sizes do not average exactly");
        if (b.image.width != a.image.width || b.image.height != a.image.height)
            throw Error(b.exr.string() + ": image size differs from " + a.exr.string());
    }
    std::vector<const Input*> by_first;
    for (const Input& in : inputs) by_first.push_back(&in);
    std::sort(by_first.begin(), by_first.end(), [](const Input* x, const Input* y) { return x->first < y->first; });
    for (size_t i = 1; i < by_first.size(); ++i)
        if (by_first[i]->first < by_first[i - 1]->first + by_first[i - 1]->count)
            throw Error(by_first[i]->exr.string() + ": passes " + std::to_string(by_first[i]->first) + ".." +
                        std::to_string(by_first[i]->first + by_first[i]->count - 1) + " overlap those of " +
                        by_first[i - 1]->exr.string() + " (render each part with its own render.first_pass)");

    MergedRun out;
    std::vector<double> sum(a.image.rgb.size(), 0.0);
    nlohmann::json from = nlohmann::json::array();
    for (const Input& in : inputs) {
        for (size_t i = 0; i < sum.size(); ++i) sum[i] += double(in.image.rgb[i]) * double(in.count);
        out.passes += in.count;
        from.push_back({{"file", in.exr.string()}, {"first_pass", in.first}, {"passes", in.count}});
    }
    out.image = Image(a.image.width, a.image.height);
    for (size_t i = 0; i < sum.size(); ++i) out.image.rgb[i] = float(sum[i] / double(out.passes));
    out.record = RunRecord::with_environment();
    // The config `vpm render MERGED.json` renders (issue 24): when the pass ranges are contiguous,
    // the one-machine run of all of them (first_pass, passes and spp of the union, no time limit),
    // which gives the merged image up to float rounding; with gaps no single run renders those
    // passes, and "reproduces" says what the config does render.
    nlohmann::json config = a.sidecar["config"];
    bool contiguous = true;
    for (size_t i = 1; i < by_first.size(); ++i)
        contiguous = contiguous && by_first[i]->first == by_first[i - 1]->first + by_first[i - 1]->count;
    const Input& first = *by_first.front();
    if (contiguous && config.contains("render") && config["render"].is_object()) {
        config["render"]["first_pass"] = first.first;
        config["render"]["passes"] = out.passes;
        config["render"]["spp"] = int64_t(out.passes) * int64_t(a.spp_per_pass);
        config["render"]["time_limit"] = 0.0;
        out.record.set("reproduces", "config renders passes " + std::to_string(first.first) + ".." +
                                         std::to_string(first.first + out.passes - 1) + ", the merged image (up to float rounding)");
    } else {
        config = first.sidecar["config"];
        out.record.set("reproduces", "config is " + first.exr.string() + "'s alone (passes " + std::to_string(first.first) +
                                         ".." + std::to_string(first.first + first.count - 1) +
                                         "): the merged pass ranges have gaps, which no single run renders");
    }
    out.record.set("config", config);
    out.record.set("merged_from", from);
    out.record.set("passes.count", out.passes);
    out.record.set("passes.first", by_first.front()->first);
    out.record.set("passes.spp_per_pass", a.spp_per_pass);
    out.exposure = a.sidecar["config"].value("/render/exposure"_json_pointer, 0.0);
    return out;
}

}  // namespace vpm
