#include "analysis/sweep/sweep_plan.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <set>
#include <sstream>

#include "analysis/sweep/row_hash.h"
#include "core/error.h"
#include "config/config_file.h"
#include "config/params.h"
#include "render/photon_map/photon_map_integrator.h"
#include "render/run/run_config.h"

namespace fs = std::filesystem;

namespace vpm {

namespace {

// TOML text of a value, as `--set key=<text>` expects it.
std::string value_text(const toml::node& n) {
    toml::table t;
    t.insert("v", n);
    std::string s = to_toml_string(t);
    const auto eq = s.find("= ");
    s = eq == std::string::npos ? s : s.substr(eq + 2);
    while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
    return s;
}

// Shortest text that reads back as the same double ("0.1", not "0.10000000000000001").
std::string short_real(double v) {
    char buf[40];
    for (int digits = 6; digits <= 17; ++digits) {
        std::snprintf(buf, sizeof buf, "%.*g", digits, v);
        if (std::strtod(buf, nullptr) == v) break;
    }
    std::string s = buf;
    if (std::isfinite(v) && s.find_first_of(".eEn") == std::string::npos) s += ".0";   // stays a float in TOML
    return s;
}

std::string value_label(const toml::node& n) {
    if (auto s = n.value_exact<std::string>()) return *s;
    if (auto d = n.value_exact<double>()) return short_real(*d);
    if (const toml::array* a = n.as_array()) {
        std::string s = "[";
        for (size_t i = 0; i < a->size(); ++i) s += (i ? ", " : "") + value_label(*a->get(i));
        return s + "]";
    }
    return value_text(n);
}

// TOML text for --set: value_label for numbers and arrays of numbers (short and exact).
std::string override_text(const toml::node& n) {
    if (n.is_string()) return value_text(n);
    if (const toml::array* a = n.as_array()) {
        for (const auto& x : *a)
            if (!x.is_number()) return value_text(n);
        return value_label(n);
    }
    if (n.is_number()) return value_label(n);
    return value_text(n);
}


}  // namespace

SweepSpec load_sweep(const std::string& path) {
    return parse_sweep(read_config_text(path, "sweep file"), path, fs::absolute(fs::path(path)).parent_path());
}

SweepSpec parse_sweep(const std::string& text, const std::string& name, const fs::path& base_dir) {
    // A sweep file is read like a config: Params reports unknown keys, types and ranges with the
    // file and line, and applies the same size and nesting limits before the TOML parser.
    const auto doc = parse_config(text, name, base_dir);
    toml::table resolved;
    Params root(doc, &resolved);
    SweepSpec s;
    s.file = name;
    if (!root.has("scene"))
        root.fail("scene", "required: the base scene config file, e.g. scene = \"../default_photon_map.toml\"");
    s.scene = root.path("scene");
    s.set = root.strings("set", {});
    s.repeats = int(root.integer("repeats", s.repeats, Range::closed(1, 100000)));
    s.time_budgets = root.reals("time_budgets", {}, Range::positive());
    s.metric = root.choice("metric", s.metric, {"relmse", "relrmse", "smape"});
    s.metric_epsilon = root.real("metric_epsilon", s.metric_epsilon, Range::positive());

    if (!root.has("reference"))
        root.fail("reference", "required table: [reference] spp = N (render it) or file = \"ref.exr\"");
    Params ref = root.table("reference");
    if (ref.has("spp")) s.reference_spp = int(ref.integer("spp", Range::closed(1, 1 << 24)));
    if (ref.has("file")) s.reference_file = ref.path("file");
    for (double d : ref.reals("path_spp", {}, Range::closed(1, 1 << 24))) {
        if (d != std::floor(d)) ref.fail("path_spp", "expected positive integers, got " + short_real(d));
        s.path_spp.push_back(int(d));
    }
    ref.finish();
    if ((s.reference_spp > 0) == !s.reference_file.empty())
        root.fail("reference", "give exactly one of spp (render a reference) and file (an EXR)");

    Params axes = root.table("axes");
    for (const std::string& key : axes.keys()) {
        const toml::node* v = axes.node(key);
        SweepAxis ax;
        ax.name = key;
        ax.key = ax.name == "k" ? "photons.k" : ax.name == "estimator" ? "photons.estimator"
                 : ax.name == "kernel" ? "photons.kernel" : ax.name == "time_limit" ? "render.time_limit" : ax.name;
        ax.line = axes.line(key);
        const toml::array* a = v->as_array();
        if (!a || a->empty()) axes.fail(key, "expected a non-empty list of values");
        for (const auto& x : *a) {
            const std::string text = override_text(x);
            if (std::find(ax.values.begin(), ax.values.end(), text) != ax.values.end())
                axes.fail(key, "the value " + value_label(x) + " is listed twice (every run would be rendered twice)");
            ax.values.push_back(text);
            ax.labels.push_back(value_label(x));
        }
        for (const auto& other : s.axes)
            if (other.key == ax.key)
                axes.fail(key, "sweeps " + ax.key + ", as axes." + other.name +
                                   " does already (k = photons.k, estimator = photons.estimator); keep one");
        if (ax.key == "render.integrator" || ax.key == "render.seed" || ax.key == "render.output")
            axes.fail(key, "cannot be swept (the sweep sets it); use repeats for seeds");
        s.axes.push_back(std::move(ax));
    }
    root.finish();
    if (!s.reference_file.empty())
        for (const auto& ax : s.axes)
            if (!ax.photon_only() && !ax.budget_only())
                throw ConfigError(name + ":" + std::to_string(ax.line) + ": axes." + ax.name +
                                  ": changes the scene, so one reference file cannot serve every run (photons.* and "
                                  "time_limit axes can); use reference.spp");
    return s;
}

namespace {

struct Built {
    toml::table resolved;
    uint64_t seed = 0;
    std::string integrator, estimator;
    int spp = 0;
};

Built build_config(const SweepSpec& spec, const std::vector<std::string>& overrides) {
    RunConfig config = RunConfig::build(load_config(spec.scene.string(), overrides));
    Built b;
    b.resolved = std::move(config.resolved);
    b.seed = config.render.seed;
    b.integrator = config.integrator->name;
    b.estimator = photon_map_settings(config).estimator.label();   // "corrected", "corrected/cone(slope=1)"
    b.spp = config.render.spp;
    return b;
}

std::string join(const std::vector<std::string>& v, const char* sep) {
    std::string s;
    for (size_t i = 0; i < v.size(); ++i) s += (i ? sep : "") + v[i];
    return s;
}

const char* const kPhotonMap = "render.integrator=\"photon_map\"";

// Every axis value on its own: the error names the axis and the value.
void validate_axis_values(const SweepSpec& spec) {
    try {
        build_config(spec, spec.set);
    } catch (const Error& e) {
        throw ConfigError(spec.file + ": scene " + spec.scene.string() + " with set = [" + join(spec.set, ", ") +
                          "]: " + e.what());
    }
    for (const auto& ax : spec.axes) {
        for (size_t i = 0; i < ax.values.size(); ++i) {
            auto ov = spec.set;
            ov.push_back(kPhotonMap);
            ov.push_back(ax.key + "=" + ax.values[i]);
            try {
                build_config(spec, ov);
            } catch (const Error& e) {
                throw ConfigError(spec.file + ":" + std::to_string(ax.line) + ": axes." + ax.name + " = " +
                                  ax.labels[i] + ": " + e.what());
            }
        }
    }
}

// One configuration of the sweep: an axes combination, or a path tracer point beside it.
struct SweepPoint {
    std::vector<std::string> overrides, values;
    std::string method;
    int spp = 0;
    Built built;
    std::string text;   // run_config_text(built.resolved)
};

std::string combination_text(const SweepSpec& spec, const std::vector<std::string>& labels) {
    std::string combo;
    for (size_t a = 0; a < spec.axes.size(); ++a) combo += (a ? ", " : "") + spec.axes[a].name + " = " + labels[a];
    return combo;
}

// The axes combination `idx` (one value index per axis) as a photon-map point, and in `scene_ov` and
// `scene_vals` its scene's overrides and labels alone (photon-only axes left out: the path tracer's).
SweepPoint combination_point(const SweepSpec& spec, const std::vector<size_t>& idx, std::vector<std::string>& scene_ov,
                             std::vector<std::string>& scene_vals) {
    SweepPoint p;
    p.overrides = spec.set;
    p.overrides.push_back(kPhotonMap);
    scene_ov = spec.set;
    scene_vals.clear();
    for (size_t a = 0; a < spec.axes.size(); ++a) {
        const auto& ax = spec.axes[a];
        const std::string o = ax.key + "=" + ax.values[idx[a]];
        p.overrides.push_back(o);
        p.values.push_back(ax.labels[idx[a]]);
        if (!ax.photon_only()) scene_ov.push_back(o);
        scene_vals.push_back(ax.photon_only() ? "" : ax.labels[idx[a]]);
    }
    try {
        p.built = build_config(spec, p.overrides);
    } catch (const Error& e) {
        throw ConfigError(spec.file + ": axes combination " + combination_text(spec, p.values) + ": " + e.what());
    }
    p.method = p.built.estimator;
    p.spp = p.built.spp;
    p.text = run_config_text(p.built.resolved);
    return p;
}

// The Cartesian product (last axis fastest), each combination followed by its path tracer points
// (one per reference.path_spp, each scene once).
std::vector<SweepPoint> sweep_points(const SweepSpec& spec) {
    std::vector<SweepPoint> points;
    std::set<std::string> path_seen;
    std::vector<size_t> idx(spec.axes.size(), 0);
    size_t combos = 1;
    for (const auto& ax : spec.axes) combos *= ax.values.size();
    for (size_t c = 0; c < combos; ++c) {
        size_t rem = c;
        for (size_t a = spec.axes.size(); a-- > 0;) {
            idx[a] = rem % spec.axes[a].values.size();
            rem /= spec.axes[a].values.size();
        }
        std::vector<std::string> scene_ov, scene_vals;
        SweepPoint p = combination_point(spec, idx, scene_ov, scene_vals);
        // Values that differ as text but not as a scene (0 and 0.0 for a float key) would
        // render the same configuration twice under two labels.
        for (const auto& q : points)
            if (q.method != "path" && q.text == p.text)
                throw ConfigError(spec.file + ": axes combinations " + combination_text(spec, q.values) + " and " +
                                  combination_text(spec, p.values) + " give the same scene; remove the duplicate value");
        points.push_back(p);
        for (int spp : spec.path_spp) {
            SweepPoint q;
            q.overrides = scene_ov;
            q.overrides.push_back("render.integrator=\"path\"");
            q.overrides.push_back("render.spp=" + std::to_string(spp));
            if (!path_seen.insert(join(q.overrides, "\n")).second) continue;
            q.values = scene_vals;
            q.method = "path";
            q.spp = spp;
            try {
                q.built = build_config(spec, q.overrides);
            } catch (const Error& e) {
                throw ConfigError(spec.file + ": reference.path_spp = " + std::to_string(spp) + ": " + e.what());
            }
            points.push_back(q);
        }
    }
    return points;
}

// The reference of a run's scene, whatever budget the runs have: its overrides without the photon
// map's, the time limit and the passes, path traced at reference_spp in independent passes (its
// variance image: the noise floor in the report), unbounded in depth.
std::vector<std::string> reference_overrides(const std::vector<std::string>& overrides, int reference_spp) {
    std::vector<std::string> ro;
    for (const auto& o : overrides)
        if (o.rfind("photons.", 0) != 0 && o.rfind("render.time_limit=", 0) != 0 && o.rfind("render.passes=", 0) != 0 &&
            o.rfind("render.first_pass=", 0) != 0)
            ro.push_back(o);
    ro.push_back("render.integrator=\"path\"");
    const int ref_spp = std::max(reference_spp, 1);
    ro.push_back("render.spp=" + std::to_string(ref_spp));
    for (int passes : {16, 8, 4, 2})
        if (ref_spp % passes == 0) {
            ro.push_back("render.passes=" + std::to_string(passes));
            break;
        }
    ro.push_back("render.max_depth=-1");
    return ro;
}

}  // namespace

SweepPlan plan_sweep(const SweepSpec& spec, const std::function<void(const std::string&)>& log) {
    SweepPlan plan;
    plan.spec = spec;
    validate_axis_values(spec);
    const std::vector<SweepPoint> points = sweep_points(spec);
    if (log) log("sweep: " + std::to_string(points.size()) + " configurations validated");

    // Runs: repeat outermost, so a partial sweep already covers every point once.
    for (int r = 0; r < spec.repeats; ++r) {
        for (const auto& p : points) {
            PlannedRun run;
            run.index = plan.runs.size();
            run.method = p.method;
            run.overrides = p.overrides;
            run.values = p.values;
            run.spp = p.spp;
            run.repeat = r;
            run.seed = p.built.seed;
            run.stream_offset = uint64_t(r);
            run.hash = run_hash(p.built.resolved, run.seed, run.stream_offset);
            run.point = hash_hex(run_config_text(p.built.resolved) + "\nseed=" + std::to_string(run.seed));
            run.scene = scene_hash(p.built.resolved);
            if (!plan.references.count(run.scene)) plan.references[run.scene] = reference_overrides(p.overrides, spec.reference_spp);
            plan.runs.push_back(std::move(run));
        }
    }
    return plan;
}

}  // namespace vpm
