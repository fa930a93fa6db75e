#include "analysis/sweep/sweep.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <fstream>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <sstream>
#include <thread>

#include <nlohmann/json.hpp>

#include "analysis/metrics/error_metrics.h"
#include "analysis/metrics/reference_noise.h"
#include "analysis/metrics/reference_samples.h"
#include "analysis/sweep/row_hash.h"
#include "analysis/sweep/sweep_csv.h"
#include "core/error.h"
#include "core/progress.h"
#include "render/run/image_io.h"
#include "render/run/run.h"
#include "render/run/run_outputs.h"
#include "render/run/run_record.h"
#include "config/params.h"
#include "render/photon_map/photon_map_stats.h"

namespace fs = std::filesystem;

namespace vpm {

namespace {

// A run without a time limit counts at an equal-time budget when its mean time is within this
// fraction over it: a 16.0003-s run is a 16-s run.
constexpr double kEqualTimeTolerance = 0.05;

std::string num(double v) {
    if (std::isnan(v)) return "nan";
    if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.10g", v);
    return buf;
}

std::string fixed(double v, int digits) {
    if (!std::isfinite(v)) return num(v);
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.*f", digits, v);
    return buf;
}

std::string sig(double v, int digits = 3) {
    if (!std::isfinite(v)) return num(v);
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.*g", digits, v);
    return buf;
}

double to_double(const std::string& s) {
    if (s.empty()) return std::nan("");
    return std::strtod(s.c_str(), nullptr);
}

void make_dir(const fs::path& p) {
    std::error_code ec;
    fs::create_directories(p, ec);
    if (ec) throw FileError(p.string() + ": cannot create folder: " + ec.message());
}

std::vector<fs::path> run_csvs(const fs::path& dir) {
    std::vector<fs::path> out;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(dir, ec)) {
        const std::string n = e.path().filename().string();
        if (e.is_regular_file() && n.rfind("runs", 0) == 0 && e.path().extension() == ".csv") out.push_back(e.path());
    }
    std::sort(out.begin(), out.end());
    return out;
}

std::string opts_sidecar_name(int shard, int shards) {
    if (shards <= 1) return "sweep.json";
    return "sweep.shard-" + std::to_string(shard) + "-of-" + std::to_string(shards) + ".json";
}

const std::vector<std::string> kBefore = {"run", "hash", "point", "scene", "method", "spp", "repeat", "seed", "stream_offset"};
// What ran (RunStats::integrator_used, gather_used, map_estimates, the photon ledger and the
// passes) sits beside the timings, so a photon-map row that path-traced shows it in the table.
// run_s is the wall time of the whole run (vpm::run: every phase, the plan's pilot included);
// total_s = trace_s + build_s + render_s leaves out the pilot and the other one-off phases.
const std::vector<std::string> kAfter = {"trace_s", "build_s", "render_s", "total_s", "run_s", "peak_rss_bytes", "photons_stored",
                                         "integrator_used", "gather_used", "map_estimates", "photons_traced", "passes",
                                         "spp_per_pass", "samples", "rel_rmse", "rel_mean_error", "nonfinite_pixels", "image", "reference"};

}  // namespace

std::vector<std::string> sweep_csv_header(const std::vector<SweepAxis>& axes) {
    std::vector<std::string> h = kBefore;
    for (const auto& a : axes) h.push_back(a.name);
    h.insert(h.end(), kAfter.begin(), kAfter.end());
    return h;
}

fs::path shard_csv_name(int shard, int shards) {
    if (shards <= 1) return "runs.csv";
    return "runs.shard-" + std::to_string(shard) + "-of-" + std::to_string(shards) + ".csv";
}

namespace {

// The runs of this shard that no CSV in the folder has finished yet (counted into `outcome`), at
// most options.max_runs of them.
std::vector<const PlannedRun*> runs_to_do(const SweepPlan& plan, const SweepOptions& opt, SweepOutcome& outcome) {
    std::set<std::string> finished;
    for (const auto& f : run_csvs(opt.out)) {
        const CsvTable t = read_csv(f);
        const int h = t.column("hash");
        if (h < 0) continue;
        for (const auto& r : t.rows) finished.insert(r[size_t(h)]);
    }
    std::vector<const PlannedRun*> todo;
    for (const auto& r : plan.runs) {
        if (int(r.index % size_t(opt.shards)) != opt.shard) continue;
        ++outcome.in_shard;
        if (finished.count(r.hash)) ++outcome.skipped;
        else todo.push_back(&r);
    }
    if (opt.max_runs > 0 && todo.size() > opt.max_runs) {
        outcome.remaining = todo.size() - opt.max_runs;
        todo.resize(opt.max_runs);
    }
    return todo;
}

// A scene's reference as the runs are scored against it.
struct SweepReference {
    Image image;
    std::string column;                 // runs.csv's reference column: the file, relative to OUT when rendered there
    std::optional<uint64_t> samples;    // its camera samples, from its sidecar
};
using SweepReferences = std::map<std::string, SweepReference>;   // by scene hash

// Renders (once per scene hash, cached in OUT/references/) or reads every reference `runs` need.
void load_references(const SweepPlan& plan, const SweepOptions& opt, const std::vector<const PlannedRun*>& runs,
                     SweepReferences& references, const std::function<void(const std::string&)>& log) {
    const SweepSpec& spec = plan.spec;
    for (const PlannedRun* r : runs) {
        if (references.count(r->scene)) continue;
        if (!spec.reference_file.empty()) {
            references[r->scene] = {read_exr(spec.reference_file), fs::absolute(spec.reference_file).string(),
                                    recorded_samples(spec.reference_file)};
            if (!references[r->scene].samples)
                log("sweep: " + spec.reference_file.string() + " has no sidecar with render.samples: the runs' samples "
                    "cannot be checked against the reference's");
            continue;
        }
        const fs::path rel = fs::path("references") / (r->scene + ".exr");
        const fs::path path = opt.out / rel;
        if (!fs::exists(path)) {
            const RunConfig config = RunConfig::build(load_config(spec.scene.string(), plan.references.at(r->scene)));
            const RenderSettings& rs = config.render;
            log("sweep: rendering reference " + r->scene + " (path tracer, " + std::to_string(rs.spp) + " spp, " +
                std::to_string(rs.width) + "x" + std::to_string(rs.height) + ")");
            RunOptions ro;
            ro.progress = opt.progress;
            ro.stream_offset = kReferenceStream;
            ro.cancelled = opt.cancelled;
            ro.pass_variance = true;
            RunResult res = vpm::run(config, ro);
            if (opt.cancelled && opt.cancelled()) return;
            // The variance first: the reference's EXR is what says the cache holds it.
            if (res.variance.width > 0) write_exr(variance_path_for(path), res.variance);
            write_run_outputs(path, res, rs.exposure);
            log("sweep: reference " + r->scene + " in " + fixed(res.stats.render.seconds, 1) + " s");
        }
        references[r->scene] = {read_exr(path), rel.string(), recorded_samples(path)};
    }
}

// One runs.csv row (sweep_csv_header's columns).
std::vector<std::string> run_row(const PlannedRun& run, const RunResult& res, double run_seconds, const RunError& err,
                                 const fs::path& image_rel, const std::string& reference) {
    const double trace = res.stats.seconds("trace"), build = res.stats.seconds("build"),
                 render = res.stats.seconds("render");
    const RunStats& st = res.stats;
    const PhotonMapStats& pm = PhotonMapStats::of(st);
    const uint64_t stored = pm.photons ? pm.photons->stored : 0;
    uint64_t traced = 0;
    if (const auto& l = pm.photon_ledger) traced = l->pass_maps + l->pilot_only + l->probe + l->decision_map;
    std::vector<std::string> row = {std::to_string(run.index), run.hash, run.point, run.scene, run.method,
                                    std::to_string(run.spp), std::to_string(run.repeat),
                                    std::to_string(run.seed), std::to_string(run.stream_offset)};
    row.insert(row.end(), run.values.begin(), run.values.end());
    const std::vector<std::string> tail = {num(trace), num(build), num(render), num(trace + build + render),
                                           num(run_seconds), std::to_string(peak_rss_bytes()), std::to_string(stored),
                                           st.integrator_used, st.gather_used.value_or("none"),
                                           std::to_string(st.map_estimates.value_or(0)), std::to_string(traced),
                                           std::to_string(st.pass_count()), std::to_string(st.pass_summary.spp),
                                           std::to_string(st.render.samples), num(err.rel_rmse), num(err.rel_mean_error),
                                           std::to_string(err.nonfinite_pixels), image_rel.string(),
                                           reference};
    row.insert(row.end(), tail.begin(), tail.end());
    return row;
}

// "ran the path tracer" / "no map estimates" for a photon-map row that did not estimate from a map;
// empty when the row ran what it was planned for.
std::string ran_instead(const std::string& method, const std::string& integrator_used, uint64_t map_estimates) {
    if (method == "path") return integrator_used == "path" || integrator_used.empty() ? "" : "ran " + integrator_used;
    if (integrator_used != "photon_map") return "ran " + (integrator_used.empty() ? std::string("?") : integrator_used);
    if (map_estimates == 0) return "no map estimates";
    return "";
}

std::string ran_instead(const std::string& method, const RunStats& stats) {
    return ran_instead(method, stats.integrator_used, stats.map_estimates.value_or(0));
}

// sweep.json (or its shard's name): the plan, the counts and the machine.
void write_sweep_sidecar(const SweepSpec& spec, const SweepOptions& opt, const SweepOutcome& outcome,
                         double run_seconds) {
    RunRecord rec = RunRecord::with_environment();
    rec.set("sweep_file", spec.file);
    rec.set("scene", spec.scene.string());
    rec.set("set", spec.set);
    rec.set("repeats", spec.repeats);
    rec.set("time_budgets", nlohmann::json(spec.time_budgets));
    rec.set("metric", spec.metric);
    rec.set("metric_epsilon", spec.metric_epsilon);
    rec.set("reference.spp", spec.reference_spp);
    rec.set("reference.file", spec.reference_file.string());
    rec.set("reference.path_spp", nlohmann::json(spec.path_spp));
    nlohmann::json axes = nlohmann::json::array();
    for (const auto& a : spec.axes) axes.push_back({{"name", a.name}, {"key", a.key}, {"values", a.labels}});
    rec.set("axes", axes);
    rec.set("command_line", opt.command_line);
    rec.set("shard.index", opt.shard);
    rec.set("shard.count", opt.shards);
    rec.set("jobs", opt.jobs);
    rec.set("runs.planned", outcome.planned);
    rec.set("runs.in_shard", outcome.in_shard);
    rec.set("runs.skipped_finished", outcome.skipped);
    rec.set("runs.ran", outcome.ran);
    rec.set("runs.remaining", outcome.remaining);
    rec.set("runs.run_seconds", run_seconds);
    rec.set("seconds", outcome.seconds);
    rec.write(opt.out / (opts_sidecar_name(opt.shard, opt.shards)));
}

// A run rendered, written to OUT/images/ with its sidecar, and scored against its reference.
struct ScoredRun {
    std::vector<std::string> row;   // its runs.csv row
    RunStats stats;
    RunError error;
    double wall = 0.0;
};

// Null when the sweep was cancelled during the run (nothing written).
std::optional<ScoredRun> render_and_score(const PlannedRun& run, const SweepSpec& spec, const SweepOptions& opt,
                                          const SweepReference& reference) {
    const RunConfig config = RunConfig::build(load_config(spec.scene.string(), run.overrides));
    RunOptions ro;
    ro.progress = false;
    ro.stream_offset = run.stream_offset;
    ro.cancelled = opt.cancelled;
    const Timer run_timer;
    RunResult res = vpm::run(config, ro);
    ScoredRun scored;
    scored.wall = run_timer.seconds();
    if (opt.cancelled && opt.cancelled()) return std::nullopt;
    const fs::path image_rel = fs::path("images") / (run.hash + ".exr");
    write_exr(opt.out / image_rel, res.image);
    res.record.write(opt.out / fs::path("images") / (run.hash + ".json"));   // the run's own sidecar
    scored.error = run_error(res.image, reference.image);
    scored.row = run_row(run, res, scored.wall, scored.error, image_rel, reference.column);
    scored.stats = std::move(res.stats);
    return scored;
}

// The run as the progress log names it: its method and axis values (and what ran instead).
std::string run_label(const PlannedRun& run, const SweepSpec& spec, const RunStats& stats) {
    std::string what = run.method;
    for (size_t a = 0; a < spec.axes.size(); ++a)
        if (!run.values[a].empty() && spec.axes[a].key != "photons.estimator")
            what += " " + spec.axes[a].name + "=" + run.values[a];
    if (run.method == "path") what += " spp=" + std::to_string(run.spp);
    if (const std::string ran = ran_instead(run.method, stats); !ran.empty()) what += " [" + ran + "]";
    return what;
}

}  // namespace

SweepOutcome run_sweep(const SweepPlan& plan, const SweepOptions& opt) {
    const Timer timer;
    auto log = [&](const std::string& s) {
        if (opt.log) opt.log(s);
    };
    if (opt.shards < 1 || opt.shard < 0 || opt.shard >= opt.shards)
        throw Error("--shard " + std::to_string(opt.shard) + "/" + std::to_string(opt.shards) +
                    ": expected i/N with 0 <= i < N");
    const SweepSpec& spec = plan.spec;
    make_dir(opt.out);
    make_dir(opt.out / "images");
    make_dir(opt.out / "references");
    SweepOutcome outcome;
    outcome.planned = plan.runs.size();
    outcome.csv = opt.out / shard_csv_name(opt.shard, opt.shards);
    const auto header = sweep_csv_header(spec.axes);
    prepare_csv(outcome.csv, header);

    std::vector<const PlannedRun*> todo = runs_to_do(plan, opt, outcome);
    log("sweep: " + std::to_string(outcome.planned) + " runs planned, " + std::to_string(outcome.in_shard) +
        " in shard " + std::to_string(opt.shard) + "/" + std::to_string(opt.shards) + ", " +
        std::to_string(outcome.skipped) + " already done, " + std::to_string(todo.size()) + " to run");

    // References: rendered once per scene hash, cached in the folder.
    SweepReferences references;
    std::vector<const PlannedRun*> need_reference = todo;
    if (opt.references_only) {
        need_reference.clear();
        for (const auto& r : plan.runs) need_reference.push_back(&r);
        todo.clear();
    }
    load_references(plan, opt, need_reference, references, log);
    auto cancelled = [&opt] { return opt.cancelled && opt.cancelled(); };
    if (cancelled()) return outcome;

    // The runs (the ETA counts from here: references are not runs).
    const Timer runs_timer;
    std::mutex mutex;
    std::atomic<size_t> next{0};
    std::atomic<bool> stop{false};
    std::exception_ptr failure;
    size_t done = 0;
    double run_seconds = 0;
    auto worker = [&] {
        while (!stop) {
            const size_t i = next++;
            if (i >= todo.size() || cancelled()) return;
            const PlannedRun& run = *todo[i];
            try {
                std::optional<ScoredRun> scored = render_and_score(run, spec, opt, references.at(run.scene));
                if (!scored) return;
                std::lock_guard<std::mutex> lock(mutex);
                append_csv_row(outcome.csv, scored->row);
                ++done;
                run_seconds += scored->wall;
                const std::string what = run_label(run, spec, scored->stats);
                const SweepReference& ref = references.at(run.scene);
                if (ref.samples)
                    if (const std::string w = more_samples_warning("run " + run.hash + " (" + what + ")",
                                                                   scored->stats.render.samples, ref.column, *ref.samples);
                        !w.empty())
                        log("sweep: " + w);
                const double el = runs_timer.seconds();
                const double eta = el / double(done) * double(todo.size() - done);
                log("sweep: [" + std::to_string(done) + "/" + std::to_string(todo.size()) + "] " + what + " r" +
                    std::to_string(run.repeat) + ": rel RMSE " + sig(scored->error.rel_rmse) + " in " + fixed(scored->wall, 2) +
                    " s" + (scored->error.nonfinite_pixels ? ", " + std::to_string(scored->error.nonfinite_pixels) + " NON-FINITE pixels" : "") +
                    "; " + fixed(el, 0) + " s elapsed, ETA " + fixed(eta, 0) + " s");
            } catch (...) {
                std::lock_guard<std::mutex> lock(mutex);
                if (!failure) failure = std::current_exception();
                stop = true;
                return;
            }
        }
    };
    const int jobs = std::max(1, std::min<int>(opt.jobs, int(std::max<size_t>(todo.size(), 1))));
    std::vector<std::thread> threads;
    for (int t = 1; t < jobs; ++t) threads.emplace_back(worker);
    worker();
    for (auto& t : threads) t.join();
    if (failure) std::rethrow_exception(failure);
    outcome.ran = done;
    if (cancelled()) return outcome;
    outcome.seconds = timer.seconds();

    write_sweep_sidecar(spec, opt, outcome, run_seconds);
    std::set<std::string> planned;
    for (const auto& r : plan.runs) planned.insert(r.hash);
    MetricOptions metric;
    metric.metric = parse_error_metric(spec.metric);
    metric.epsilon = spec.metric_epsilon;
    write_sweep_report(opt.out, spec.time_budgets, spec.file, planned, metric);
    return outcome;
}

namespace {

struct Row {
    std::vector<std::string> f;
};

struct PointStats {
    size_t first_run = 0;
    std::string point, method, spp, scene;
    std::vector<std::string> values;
    std::vector<const Row*> rows;
    double trace = 0, build = 0, render = 0, total = 0, stored = 0;
    double wall = 0;   // mean run_s (total_s in folders written before run_s existed): the report's time
    // What ran, over the repeats: the distinct integrator_used / gather_used values ("/"-joined),
    // the mean map estimates, and the repeats that did not run what the point was planned for.
    std::set<std::string> integrator_set, gather_set;
    std::string integrators, gathers;   // the sets joined, in order (the same for any row order)
    double map_estimates = 0;
    size_t off_plan = 0;
    size_t over_reference = 0;   // repeats that took more camera samples than their reference
    RepeatError err;
    // The report's named metric (error_metrics.h) over the repeats: the mean of the per-repeat values
    // (noise floor subtracted when the reference has a variance image), its standard error (NaN for
    // one repeat), the mean raw value and the floor (NaN: unknown).
    double error = 0, error_se = 0, error_raw = 0, noise_floor = 0;
};

// Every row of the folder's runs*.csv once, and the columns the report reads.
struct RunTable {
    std::vector<std::string> header;
    std::vector<Row> rows;
    size_t run = 0, point = 0, method = 0, spp = 0, offset = 0, trace = 0, total = 0, build = 0, render = 0,
           stored = 0, image = 0, ref = 0;
    // What-ran columns; -1 in folders written before they existed (the report shows "?").
    int integrator = -1, gather = -1, estimates = -1, wall = -1, samples = -1;
    std::vector<std::string> axes;   // the axis columns, between stream_offset and trace_s
};

RunTable read_run_table(const fs::path& out, const std::set<std::string>& only) {
    RunTable t;
    std::set<std::string> seen;
    for (const auto& f : run_csvs(out)) {
        const CsvTable csv = read_csv(f);
        if (t.header.empty()) t.header = csv.header;
        else if (csv.header != t.header) throw FileError(f.string() + ": its header differs from the other runs*.csv in " + out.string());
        const int h = csv.column("hash");
        for (const auto& r : csv.rows)
            if ((only.empty() || only.count(r[size_t(h)])) && seen.insert(r[size_t(h)]).second) t.rows.push_back({r});
    }
    if (t.header.empty()) throw FileError(out.string() + ": no runs*.csv to report on");
    auto col = [&](const char* name) {
        const auto it = std::find(t.header.begin(), t.header.end(), name);
        if (it == t.header.end()) throw FileError(out.string() + ": runs.csv has no column '" + name + "'");
        return size_t(it - t.header.begin());
    };
    t.run = col("run"), t.point = col("point"), t.method = col("method"), t.spp = col("spp");
    t.offset = col("stream_offset"), t.trace = col("trace_s"), t.total = col("total_s"), t.build = col("build_s");
    t.render = col("render_s"), t.stored = col("photons_stored"), t.image = col("image"), t.ref = col("reference");
    auto optional_col = [&](const char* name) {
        const auto it = std::find(t.header.begin(), t.header.end(), name);
        return it == t.header.end() ? -1 : int(it - t.header.begin());
    };
    t.integrator = optional_col("integrator_used"), t.gather = optional_col("gather_used");
    t.estimates = optional_col("map_estimates"), t.wall = optional_col("run_s"), t.samples = optional_col("samples");
    t.axes.assign(t.header.begin() + long(t.offset) + 1, t.header.begin() + long(t.trace));
    return t;
}

// The rows grouped by configuration (point), grouped by method in order of first appearance and
// in plan order within a method.
std::vector<PointStats*> group_points(const RunTable& t, std::map<std::string, PointStats>& by_point) {
    for (const auto& r : t.rows) {
        PointStats& p = by_point[r.f[t.point]];
        const size_t run = size_t(std::stoull(r.f[t.run]));
        if (p.rows.empty() || run < p.first_run) p.first_run = run;
        if (p.rows.empty()) {
            p.point = r.f[t.point];
            p.method = r.f[t.method];
            p.spp = r.f[t.spp];
            p.scene = r.f[t.ref];   // the reference identifies the scene
            p.values.assign(r.f.begin() + long(t.offset) + 1, r.f.begin() + long(t.trace));
        }
        p.rows.push_back(&r);
    }
    std::vector<PointStats*> points;
    for (auto& [k, p] : by_point) points.push_back(&p);
    std::sort(points.begin(), points.end(), [](auto* a, auto* b) { return a->first_run < b->first_run; });
    std::vector<std::string> order;
    for (auto* p : points)
        if (std::find(order.begin(), order.end(), p->method) == order.end()) order.push_back(p->method);
    auto rank = [&](const PointStats* p) { return std::find(order.begin(), order.end(), p->method) - order.begin(); };
    std::stable_sort(points.begin(), points.end(), [&](auto* a, auto* b) { return rank(a) < rank(b); });
    return points;
}

// Mean timings and the error over repeats of every point against its reference; returns the
// number of non-finite pixels seen.
size_t measure_points(const fs::path& out, const RunTable& t, const std::vector<PointStats*>& points,
                      const MetricOptions& metric) {
    auto in_out = [&](const std::string& col) { return fs::path(col).is_absolute() ? fs::path(col) : out / col; };
    std::map<std::string, NoisyReference> noisy_refs;
    std::map<std::string, Image> refs;
    std::map<std::string, std::optional<uint64_t>> ref_samples;
    size_t nonfinite_total = 0;
    for (PointStats* p : points) {
        const fs::path ref_path = in_out(p->rows[0]->f[t.ref]);
        if (!refs.count(ref_path.string())) {
            noisy_refs[ref_path.string()] = load_reference(ref_path);   // with REF.variance.exr when there is one
            refs[ref_path.string()] = noisy_refs[ref_path.string()].image;
            ref_samples[ref_path.string()] = recorded_samples(ref_path);
        }
        const NoisyReference& noisy = noisy_refs.at(ref_path.string());
        const std::optional<uint64_t> reference_samples = ref_samples.at(ref_path.string());
        std::vector<Image> images;
        images.reserve(p->rows.size());
        for (const Row* r : p->rows) {
            images.push_back(read_exr(in_out(r->f[t.image])));
            p->trace += to_double(r->f[t.trace]);
            p->build += to_double(r->f[t.build]);
            p->render += to_double(r->f[t.render]);
            p->total += to_double(r->f[t.total]);
            p->wall += to_double(r->f[t.wall >= 0 ? size_t(t.wall) : t.total]);
            p->stored += to_double(r->f[t.stored]);
            const std::string integrator = t.integrator >= 0 ? r->f[size_t(t.integrator)] : "";
            const double estimates = t.estimates >= 0 ? to_double(r->f[size_t(t.estimates)]) : std::nan("");
            p->integrator_set.insert(integrator.empty() ? "?" : integrator);
            const std::string gather = t.gather >= 0 ? r->f[size_t(t.gather)] : "";
            p->gather_set.insert(gather.empty() ? "?" : gather);
            p->map_estimates += estimates;
            if (t.samples >= 0 && reference_samples && to_double(r->f[size_t(t.samples)]) > double(*reference_samples))
                ++p->over_reference;
            if (t.integrator >= 0 && !ran_instead(p->method, integrator, uint64_t(std::isfinite(estimates) ? estimates : 0)).empty())
                ++p->off_plan;
        }
        auto join = [](const std::set<std::string>& v) {
            std::string s;
            for (const auto& x : v) s += (s.empty() ? "" : "/") + x;
            return s;
        };
        p->integrators = join(p->integrator_set), p->gathers = join(p->gather_set);
        const double n = double(p->rows.size());
        p->trace /= n, p->build /= n, p->render /= n, p->total /= n, p->wall /= n, p->stored /= n, p->map_estimates /= n;
        std::vector<const Image*> ptrs;
        for (const auto& im : images) ptrs.push_back(&im);
        p->err = repeat_error(ptrs, refs.at(ref_path.string()));
        nonfinite_total += p->err.nonfinite_pixels;
        std::vector<double> values;
        p->error_raw = 0;
        for (const Image& im : images) {
            const MetricValue m = measure_error(im, noisy.image, metric, noisy.variance ? &*noisy.variance : nullptr);
            values.push_back(m.value);
            p->error_raw += m.raw / n;
            p->noise_floor = m.floor;
        }
        p->error = 0;
        for (double v : values) p->error += v / n;
        double var = 0;
        for (double v : values) var += values.size() > 1 ? (v - p->error) * (v - p->error) / (n - 1) : 0.0;
        p->error_se = values.size() > 1 ? std::sqrt(var / n) : std::nan("");
    }
    return nonfinite_total;
}

void write_points_csv(const fs::path& out, const std::vector<std::string>& axes, const std::vector<PointStats*>& points,
                      const MetricOptions& metric) {
    std::vector<std::string> ph = {"point", "method", "spp"};
    ph.insert(ph.end(), axes.begin(), axes.end());
    for (const char* c : {"repeats", "trace_s", "build_s", "render_s", "total_s", "run_s", "photons_stored", "integrator_used",
                          "gather_used", "map_estimates", "off_plan_repeats", "rel_rmse", "rel_mse",
                          "rel_bias", "rel_bias_se", "rel_bias2", "rel_variance", "rel_std", "nonfinite_pixels", "metric",
                          "error", "error_se", "error_raw", "noise_floor"})
        ph.push_back(c);
    std::string pcsv = csv_line(ph);
    for (const PointStats* p : points) {
        std::vector<std::string> f = {p->point, p->method, p->spp};
        f.insert(f.end(), p->values.begin(), p->values.end());
        const RepeatError& e = p->err;
        for (const std::string& v :
             {std::to_string(e.repeats), num(p->trace), num(p->build), num(p->render), num(p->total), num(p->wall), num(p->stored),
              p->integrators, p->gathers, num(p->map_estimates), std::to_string(p->off_plan), num(e.rel_rmse), num(e.rel_mse), num(e.rel_bias), num(e.rel_bias_se), num(e.rel_bias2), num(e.rel_variance),
              num(e.rel_std), std::to_string(e.nonfinite_pixels), metric_name(metric.metric), num(p->error), num(p->error_se),
              num(p->error_raw), num(p->noise_floor)})
            f.push_back(v);
        pcsv += csv_line(f);
    }
    write_text_atomic(out / "points.csv", pcsv);
}

// summary.md's table of every configuration; `shown`: the axes given their own column.
std::string configurations_md(const std::vector<std::string>& axes, const std::vector<size_t>& shown,
                              const std::vector<PointStats*>& points, const MetricOptions& metric) {
    // Spread needs two repeats: with one, say so ("–") instead of printing nan.
    auto or_dash = [](double v, int digits = 3) { return std::isfinite(v) ? sig(v, digits) : std::string("–"); };
    std::ostringstream md;
    md << "## Configurations\n\n| method |";
    for (size_t a : shown) md << " " << axes[a] << " |";
    md << " spp | ran (gather) | R | time s | " << metric_name(metric.metric)
       << " ± SE | noise floor | rel RMSE | rel bias ± SE | rel std | rel bias² | rel var | NaN/Inf |\n|---|";
    for (size_t i = 0; i < shown.size(); ++i) md << "---:|";
    md << "---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    for (const PointStats* p : points) {
        const RepeatError& e = p->err;
        md << "| " << p->method << " |";
        for (size_t a : shown) md << " " << (p->values[a].empty() ? "–" : p->values[a]) << " |";
        std::string ran = p->integrators + (p->gathers == "none" || p->gathers == "?" ? "" : " (" + p->gathers + ")");
        if (p->off_plan) ran = "**" + ran + "**";   // a photon-map point that did not estimate from a map
        md << " " << p->spp << " | " << ran << " | " << e.repeats << " | " << sig(p->wall) << " | " << sig(p->error) << " ± "
           << or_dash(p->error_se, 2) << " | " << or_dash(p->noise_floor) << " | " << sig(e.rel_rmse) << " | "
           << sig(e.rel_bias) << " ± " << or_dash(e.rel_bias_se, 2) << " | " << or_dash(e.rel_std) << " | " << sig(e.rel_bias2)
           << " | " << or_dash(e.rel_variance) << " | " << e.nonfinite_pixels << " |\n";
    }
    return md.str();
}

// The axis that sets render.time_limit ("time_limit" or its dotted key), or -1.
int time_limit_axis(const std::vector<std::string>& axes) {
    for (size_t a = 0; a < axes.size(); ++a)
        if (axes[a] == "time_limit" || axes[a] == "render.time_limit") return int(a);
    return -1;
}

// summary.md's equal-time tables: per scene, budget and method, the lowest error of the report's
// metric. A run with a time limit counts at the budget equal to its limit only (each budget row
// shows the runs made for it: no run fills two rows, and an overrun is printed, not hidden); a run
// without one counts at every budget its mean time fits within, to kEqualTimeTolerance.
std::string equal_time_md(const std::vector<std::string>& axes, const std::vector<size_t>& shown,
                          const std::vector<PointStats*>& points, std::vector<double> budgets, const MetricOptions& metric) {
    const int tl = time_limit_axis(axes);
    auto limit_of = [&](const PointStats* p) {
        return tl >= 0 && !p->values[size_t(tl)].empty() ? to_double(p->values[size_t(tl)]) : std::nan("");
    };
    if (budgets.empty() && tl >= 0) {
        for (const PointStats* p : points)
            if (const double l = limit_of(p); std::isfinite(l) && std::find(budgets.begin(), budgets.end(), l) == budgets.end())
                budgets.push_back(l);
        std::sort(budgets.begin(), budgets.end());
    }
    if (budgets.empty() && !points.empty()) {
        double lo = kInfinity, hi = 0;
        for (const PointStats* p : points) lo = std::min(lo, p->wall), hi = std::max(hi, p->wall);
        if (lo > 0 && hi > 0)
            for (double f : {1.0 / 3.0, 2.0 / 3.0, 1.0}) budgets.push_back(lo * std::pow(hi / lo, f));
    }
    auto same_budget = [](double a, double b) { return std::abs(a - b) <= 1e-9 * std::max(std::abs(a), std::abs(b)); };
    auto counts_at = [&](const PointStats* p, double b) {
        const double l = limit_of(p);
        return std::isfinite(l) ? same_budget(l, b) : p->wall <= b * (1.0 + kEqualTimeTolerance);
    };
    std::vector<std::string> methods, scenes;
    for (const PointStats* p : points) {
        if (std::find(methods.begin(), methods.end(), p->method) == methods.end()) methods.push_back(p->method);
        if (std::find(scenes.begin(), scenes.end(), p->scene) == scenes.end()) scenes.push_back(p->scene);
    }
    std::ostringstream md;
    md << "\n## Equal time\n\nLowest " << metric_name(metric.metric) << " (" << metric_formula(metric.metric, metric.epsilon)
       << ", the reference's noise floor subtracted where known; ± its standard error over the repeats) each method reaches at "
       << "the budget, its mean run time and the configuration that reaches it; one table per scene (each scene has its own "
       << "reference). A run with render.time_limit counts at the budget equal to its limit; a run without one at every budget "
       << "its mean time fits within (+" << sig(100 * kEqualTimeTolerance, 2) << "%).\n";
    auto photon_axis = [](const std::string& a) {
        return a == "k" || a == "estimator" || a == "kernel" || a.rfind("photons.", 0) == 0;
    };
    size_t empty_cells = 0;
    for (const auto& sc : scenes) {
        std::vector<const PointStats*> sp;
        for (const PointStats* p : points)
            if (p->scene == sc) sp.push_back(p);
        std::string scene_cfg;
        for (size_t a = 0; a < axes.size(); ++a)
            if (!photon_axis(axes[a]) && int(a) != tl && !sp[0]->values[a].empty())
                scene_cfg += (scene_cfg.empty() ? "" : ", ") + axes[a] + "=" + sp[0]->values[a];
        md << "\n";
        if (scenes.size() > 1) md << "### " << (scene_cfg.empty() ? sc : scene_cfg) << "\n\n";
        md << "| budget s |";
        for (const auto& m : methods) md << " " << m << " |";
        md << "\n|---:|";
        for (size_t i = 0; i < methods.size(); ++i) md << "---|";
        md << "\n";
        for (double b : budgets) {
            md << "| " << sig(b) << " |";
            for (const auto& m : methods) {
                const PointStats* best = nullptr;
                for (const PointStats* p : sp)
                    if (p->method == m && counts_at(p, b) && std::isfinite(p->error) && (!best || p->error < best->error))
                        best = p;
                if (!best) {
                    ++empty_cells;
                    md << " – |";
                    continue;
                }
                md << " " << sig(best->error) << (std::isfinite(best->error_se) ? " ± " + sig(best->error_se, 2) : std::string())
                   << " at " << sig(best->wall) << " s";
                if (best->wall > b * (1.0 + kEqualTimeTolerance)) md << " **(" << sig(best->wall / b, 2) << "x the budget)**";
                std::string cfg;
                for (size_t a : shown)
                    if (int(a) != tl && !best->values[a].empty() && photon_axis(axes[a]))
                        cfg += (cfg.empty() ? "" : ", ") + axes[a] + "=" + best->values[a];
                if (m == "path" && tl < 0) cfg += (cfg.empty() ? "" : ", ") + std::string("spp=") + best->spp;
                if (!cfg.empty()) md << " (" << cfg << ")";
                md << (best->off_plan ? " **ran " + best->integrators + "**" : "") << " |";
            }
            md << "\n";
        }
    }
    if (empty_cells)
        md << "\n–: no run of that method fits within the budget (its runs are all slower), or none has a finite error.\n";
    return md.str();
}

}  // namespace

std::string write_sweep_report(const fs::path& out, const std::vector<double>& budgets, const std::string& title,
                               const std::set<std::string>& only, const MetricOptions& metric) {
    const RunTable table = read_run_table(out, only);
    std::map<std::string, PointStats> by_point;
    const std::vector<PointStats*> points = group_points(table, by_point);
    const size_t nonfinite_total = measure_points(out, table, points, metric);
    write_points_csv(out, table.axes, points, metric);

    std::vector<size_t> shown;   // axes with their own column (estimator and kernel are in the method label)
    for (size_t a = 0; a < table.axes.size(); ++a)
        if (table.axes[a] != "estimator" && table.axes[a] != "kernel") shown.push_back(a);
    std::ostringstream md;
    md << "# Sweep: " << title << "\n\n"
       << table.rows.size() << " runs in " << points.size() << " configurations. Error: **" << metric_name(metric.metric)
       << "** = " << metric_formula(metric.metric, metric.epsilon).substr(metric_name(metric.metric).size() + 3) << ", "
       << (metric_has_floor(metric.metric) ? "the reference's noise floor (its variance image, when it has one) subtracted"
                                           : "no noise floor subtracted (not a squared error)")
       << "; rel RMSE, bias and variance are relative to the reference's mean luminance, noise included "
       << "(docs/metrics.md; docs/experiments.md, Parameter sweeps). Times are means over the repeats of each run's wall time (run_s: every phase, the plan's pilot included; seconds).\n\n";
    if (nonfinite_total)
        md << "**WARNING: " << nonfinite_total << " non-finite (NaN/Inf) pixels across the runs; they are left out of the "
           << "metrics. See the nonfinite_pixels column.**\n\n";
    size_t off_plan_points = 0, off_plan_runs = 0, over_reference = 0;
    bool one_repeat = false;
    for (const PointStats* p : points) {
        over_reference += p->over_reference;
        off_plan_points += p->off_plan > 0;
        off_plan_runs += p->off_plan;
        one_repeat |= p->err.repeats < 2;
    }
    if (off_plan_points)
        md << "**WARNING: " << off_plan_runs << " runs of " << off_plan_points << " photon-map configurations did not "
           << "estimate from a photon map (they ran the path tracer, or took no map estimates): their errors are not the "
           << "estimator's. They are in bold in the \"ran\" column; see integrator_used and map_estimates in runs.csv and "
           << "each run's sidecar images/<hash>.json.**\n\n";
    if (over_reference)
        md << "**WARNING: " << over_reference << " runs took more camera samples than their reference (runs.csv samples "
           << "against the reference's sidecar): their errors are then mostly the reference's own noise. Render the "
           << "reference with many more samples.**\n\n";
    if (one_repeat)
        md << "Configurations with one repeat (R = 1) leave the standard error, rel std and rel var empty (–): they "
           << "need two or more independent repeats (repeats = 2 or more in the sweep file).\n\n";
    md << configurations_md(table.axes, shown, points, metric) << equal_time_md(table.axes, shown, points, budgets, metric);
    // The plots are listed only once they exist: plot_sweep adds the line (not under --no-plots).
    write_text_atomic(out / "summary.md", md.str());
    return md.str();
}

size_t merge_sweeps(const std::vector<fs::path>& dirs, const fs::path& out,
                    const std::function<void(const std::string&)>& log) {
    if (dirs.empty()) throw Error("merge: no folders given");
    make_dir(out);
    const fs::path out_abs = fs::weakly_canonical(fs::absolute(out));
    std::vector<std::string> header;
    std::string text;
    std::set<std::string> seen;
    size_t rows = 0, duplicates = 0;
    fs::path sidecar;
    for (const auto& dir : dirs) {
        if (!fs::is_directory(dir)) throw FileError(dir.string() + ": not a folder");
        const auto csvs = run_csvs(dir);
        if (csvs.empty()) throw FileError(dir.string() + ": no runs*.csv in it (not a sweep --out folder?)");
        if (sidecar.empty())
            for (const auto& e : fs::directory_iterator(dir))
                if (e.path().extension() == ".json" && e.path().filename().string().rfind("sweep", 0) == 0) sidecar = e.path();
        const fs::path dir_abs = fs::weakly_canonical(fs::absolute(dir));
        for (const auto& f : csvs) {
            const CsvTable t = read_csv(f);
            if (header.empty()) {
                header = t.header;
                text = csv_line(header);
            } else if (t.header != header) {
                throw FileError(f.string() + ": its columns differ from " + dirs[0].string() + " (another sweep?)");
            }
            const int h = t.column("hash"), im = t.column("image"), rf = t.column("reference");
            if (h < 0 || im < 0 || rf < 0) throw FileError(f.string() + ": not a sweep runs CSV");
            for (auto r : t.rows) {
                if (!seen.insert(r[size_t(h)]).second) {
                    ++duplicates;
                    continue;
                }
                for (int c : {im, rf}) {
                    const fs::path p(r[size_t(c)]);
                    if (p.is_relative()) r[size_t(c)] = fs::relative(dir_abs / p, out_abs).string();
                }
                text += csv_line(r);
                ++rows;
            }
        }
    }
    // Other runs*.csv already in `out` (its own shards when merging in place) are read too by the
    // report, which drops duplicate hashes, so they never double-count.
    write_text_atomic(out / "runs.csv", text);
    if (!sidecar.empty() && !fs::exists(out / "sweep.json")) fs::copy_file(sidecar, out / "sweep.json");
    if (log)
        log("merge: " + std::to_string(rows) + " rows from " + std::to_string(dirs.size()) + " folders, " +
            std::to_string(duplicates) + " duplicates dropped -> " + (out / "runs.csv").string());
    std::vector<double> budgets;
    std::string title = "merged";
    MetricOptions metric;
    if (fs::exists(out / "sweep.json")) {
        std::ifstream in(out / "sweep.json");
        const auto j = nlohmann::json::parse(in, nullptr, false);
        if (!j.is_discarded()) {
            if (j.contains("time_budgets") && j["time_budgets"].is_array())
                for (const auto& b : j["time_budgets"]) budgets.push_back(b.get<double>());
            if (j.contains("sweep_file") && j["sweep_file"].is_string()) title = j["sweep_file"].get<std::string>();
            if (j.contains("metric") && j["metric"].is_string()) metric.metric = parse_error_metric(j["metric"].get<std::string>());
            if (j.contains("metric_epsilon") && j["metric_epsilon"].is_number()) metric.epsilon = j["metric_epsilon"].get<double>();
        }
    }
    write_sweep_report(out, budgets, title, {}, metric);
    return rows;
}

bool plot_sweep(const fs::path& out, const fs::path& script, const std::function<void(const std::string&)>& log) {
    auto quote = [](const std::string& s) {
        std::string q = "'";
        for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
        return q + "'";
    };
    if (!fs::exists("/usr/bin/python3") || !fs::exists(script)) {
        if (log) log("sweep: plots skipped (/usr/bin/python3 or " + script.string() + " missing); the tables are written");
        return false;
    }
    const std::string cmd = "/usr/bin/python3 " + quote(script.string()) + " " + quote(out.string());
    const int rc = std::system(cmd.c_str());
    if (rc != 0) {
        if (log) log("sweep: plotting failed (exit " + std::to_string(rc) + "; is python3-matplotlib installed?); the tables are written");
        return false;
    }
    if (log) log("sweep: plots in " + out.string() + " (error_vs_time, error_vs_k, bias_vs_k: .png, .pdf, .svg)");
    std::ifstream in(out / "summary.md");
    std::stringstream md;
    md << in.rdbuf();
    md << "\nPlots (tools/plot_sweep.py), each as .png, .pdf and .svg: error_vs_time (error bars: standard error over "
          "the repeats; the dashed line: the reference's noise floor), error_vs_k, bias_vs_k.\n";
    write_text_atomic(out / "summary.md", md.str());
    return true;
}

}  // namespace vpm
