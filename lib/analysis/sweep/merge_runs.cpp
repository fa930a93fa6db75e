#include "analysis/sweep/merge_runs.h"

#include <algorithm>
#include <cstdint>
#include <fstream>

#include <nlohmann/json.hpp>

#include "analysis/sweep/row_hash.h"
#include "core/error.h"
#include "render/run/image_io.h"

namespace vpm {

namespace {

struct Input {
    std::filesystem::path exr;
    nlohmann::json sidecar;
    Image image;
    int64_t first = 0, count = 0, spp_per_pass = 0;
    double exposure = 0.0;
};

// Sidecar values are checked like config keys: one error naming the file, the key, what it must be
// and what it is. Pass indices and counts are bounded so that first + count and the sum of the
// counts fit in any integer vpm uses for them (int64 here, int in a render).
constexpr int64_t kMaxPassIndex = 2147483647;   // INT_MAX

std::string shown(const nlohmann::json& v) {
    std::string s = v.dump();
    return s.size() > 40 ? s.substr(0, 37) + "..." : s;
}

int64_t sidecar_integer(const nlohmann::json& table, const char* key, const std::string& where, int64_t lo,
                        int64_t hi) {
    const std::string name = std::string("passes.") + key;
    if (!table.contains(key)) throw FileError(where + ": " + name + " is missing (an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "])");
    const nlohmann::json& v = table[key];
    // is_number_integer is false for 2.5; nlohmann stores 2.0 as a float, refused as well
    if (!v.is_number_integer() || (v.is_number_unsigned() && v.get<uint64_t>() > uint64_t(hi)) ||
        v.get<int64_t>() < lo || v.get<int64_t>() > hi)
        throw FileError(where + ": " + name + ": expected an integer in [" + std::to_string(lo) + ", " +
                        std::to_string(hi) + "], got " + shown(v));
    return v.get<int64_t>();
}

Input read_input(const std::filesystem::path& exr) {
    Input in;
    in.exr = exr;
    const std::filesystem::path json = sidecar_path_for(exr);
    const std::string where = json.string();
    std::ifstream f(json);
    if (!f) throw FileError(where + ": cannot read the sidecar of " + exr.string() + " (vpm merge needs both)");
    in.sidecar = nlohmann::json::parse(f, nullptr, false);
    if (in.sidecar.is_discarded() || !in.sidecar.is_object() || !in.sidecar.contains("config") ||
        !in.sidecar.contains("passes"))
        throw FileError(where + ": not a vpm render sidecar with \"config\" and \"passes\"");
    if (!in.sidecar["config"].is_object())
        throw FileError(where + ": config: expected an object (the resolved config), got " + shown(in.sidecar["config"]));
    const nlohmann::json& p = in.sidecar["passes"];
    if (!p.is_object()) throw FileError(where + ": passes: expected an object with first, count and spp_per_pass, got " + shown(p));
    in.first = p.contains("first") ? sidecar_integer(p, "first", where, 0, kMaxPassIndex) : 0;   // default as in a config
    in.count = sidecar_integer(p, "count", where, 1, kMaxPassIndex + 1);
    if (in.first + in.count - 1 > kMaxPassIndex)
        throw FileError(where + ": passes.first + passes.count - 1 = " + std::to_string(in.first + in.count - 1) +
                        " exceeds the largest pass index " + std::to_string(kMaxPassIndex));
    in.spp_per_pass = sidecar_integer(p, "spp_per_pass", where, 1, 1 << 24);
    const nlohmann::json& config = in.sidecar["config"];
    if (config.contains("render") && !config["render"].is_object())
        throw FileError(where + ": config.render: expected an object, got " + shown(config["render"]));
    if (config.contains("render") && config["render"].contains("exposure")) {
        const nlohmann::json& e = config["render"]["exposure"];
        if (!e.is_number() || !(e.get<double>() >= -64.0 && e.get<double>() <= 64.0))
            throw FileError(where + ": config.render.exposure: expected a number in [-64, 64], got " + shown(e));
        in.exposure = e.get<double>();
    }
    in.image = read_exr(exr);
    return in;
}

// The seconds of a sidecar's phases, summed (0 when it has none).
double phase_seconds(const nlohmann::json& sidecar) {
    double s = 0.0;
    if (sidecar.contains("phases") && sidecar["phases"].is_object())
        for (const auto& [name, p] : sidecar["phases"].items())
            if (p.is_object() && p.contains("seconds") && p["seconds"].is_number()) s += p["seconds"].get<double>();
    return s;
}

// What ran, over the inputs: integrator_used and gather_used (the inputs' common value, or their
// distinct values joined by "/" when the parts differ, e.g. an "auto" plan that chose differently),
// map_estimates, the photons.traced ledger and render.samples summed, and "seconds": every input's
// phases summed (the machine time the merged passes took). Keys no input has are left out.
void record_what_ran(const std::vector<Input>& inputs, RunRecord& record) {
    for (const char* key : {"integrator_used", "gather_used"}) {
        std::string joined;
        for (const Input& in : inputs) {
            if (!in.sidecar.contains(key) || !in.sidecar[key].is_string()) continue;
            const std::string v = in.sidecar[key].get<std::string>();
            if (("/" + joined + "/").find("/" + v + "/") == std::string::npos) joined += (joined.empty() ? "" : "/") + v;
        }
        if (!joined.empty()) record.set(key, joined);
    }
    auto sum = [&](const std::vector<const char*>& path, const std::string& dotted) {
        uint64_t total = 0;
        bool any = false;
        for (const Input& in : inputs) {
            const nlohmann::json* j = &in.sidecar;
            for (const char* p : path) {
                if (!j || !j->is_object() || !j->contains(p)) {
                    j = nullptr;
                    break;
                }
                j = &(*j)[p];
            }
            if (!j || !j->is_number_unsigned()) continue;
            total += j->get<uint64_t>();
            any = true;
        }
        if (any) record.set(dotted, total);
    };
    sum({"map_estimates"}, "map_estimates");
    sum({"render", "samples"}, "render.samples");
    for (const char* k : {"pass_maps", "passes", "estimates", "pilot_only", "probe", "decision_map", "decision_queries"})
        sum({"photons", "traced", k}, std::string("photons.traced.") + k);
    double seconds = 0.0;
    for (const Input& in : inputs) seconds += phase_seconds(in.sidecar);
    if (seconds > 0) record.set("seconds", seconds);
}

}  // namespace

std::string merge_identity(const nlohmann::json& config) {
    nlohmann::json c = config;
    if (c.contains("render") && c["render"].is_object())
        for (const char* k : {"output", "threads", "passes", "first_pass", "spp", "time_limit", "time_limit_passes", "exposure"})
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
                        " (resolved configs differ beyond output, threads, passes, first_pass, spp, time_limit, time_limit_passes, "
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
        nlohmann::json entry = {{"file", in.exr.string()}, {"first_pass", in.first}, {"passes", in.count}};
        for (const char* k : {"integrator_used", "gather_used", "map_estimates"})
            if (in.sidecar.contains(k)) entry[k] = in.sidecar[k];
        if (const double s = phase_seconds(in.sidecar); s > 0) entry["seconds"] = s;
        from.push_back(entry);
    }
    out.image = Image(a.image.width, a.image.height);
    for (size_t i = 0; i < sum.size(); ++i) out.image.rgb[i] = float(sum[i] / double(out.passes));
    out.record = RunRecord::with_environment();
    // The config `vpm render MERGED.json` renders: when the pass ranges are contiguous,
    // the one-machine run of all of them (first_pass, passes and spp of the union, no time limit),
    // which gives the merged image up to float rounding; with gaps no single run renders those
    // passes, and "reproduces" says what the config does render.
    nlohmann::json config = a.sidecar["config"];
    bool contiguous = true;
    for (size_t i = 1; i < by_first.size(); ++i)
        contiguous = contiguous && by_first[i]->first == by_first[i - 1]->first + by_first[i - 1]->count;
    const Input& first = *by_first.front();
    const bool one_run = contiguous && config.contains("render") && config["render"].is_object();
    if (one_run) {
        config["render"]["first_pass"] = first.first;
        config["render"]["passes"] = out.passes;
        config["render"]["spp"] = int64_t(out.passes) * int64_t(a.spp_per_pass);
        config["render"]["time_limit"] = 0.0;
        config["render"].erase("time_limit_passes");
        out.record.set("reproduces", "config renders passes " + std::to_string(first.first) + ".." +
                                         std::to_string(first.first + out.passes - 1) + ", the merged image (up to float rounding)");
    } else {
        config = first.sidecar["config"];
        out.record.set("reproduces", "config is " + first.exr.string() + "'s alone (passes " + std::to_string(first.first) +
                                         ".." + std::to_string(first.first + first.count - 1) +
                                         "): the merged pass ranges have gaps, which no single run renders");
    }
    out.record.set("config", config);
    // The keys the config leaves to their defaults (render/run/run.cpp), less those set above.
    const nlohmann::json& source = one_run ? a.sidecar : first.sidecar;
    if (source.contains("config_defaults") && source["config_defaults"].is_array()) {
        nlohmann::json defaults = nlohmann::json::array();
        for (const nlohmann::json& key : source["config_defaults"])
            if (!one_run || !(key == "render.first_pass" || key == "render.passes" || key == "render.spp" ||
                                 key == "render.time_limit" || key == "render.time_limit_passes"))
                defaults.push_back(key);
        out.record.set("config_defaults", defaults);
    }
    out.record.set("merged_from", from);
    out.record.set("passes.count", out.passes);
    out.record.set("passes.first", by_first.front()->first);
    out.record.set("passes.spp_per_pass", a.spp_per_pass);
    record_what_ran(inputs, out.record);
    out.exposure = a.exposure;
    return out;
}

}  // namespace vpm
