// vpm sweep (lib/analysis/sweep*.h): resume, shards + merge, validation before any work, CSV.
// A tiny scene (8x8, homogeneous sphere, a few hundred photons) keeps every sweep well under a second.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <string>

#include "analysis/sweep/row_hash.h"
#include "analysis/sweep/sweep.h"
#include "render/run/run.h"
#include "render/run/run_config.h"
#include "render/run/run_outputs.h"
#include "analysis/sweep/sweep_csv.h"
#include "analysis/sweep/sweep_plan.h"
#include "core/error.h"
#include "config/params.h"
#include "render/run/run_config.h"

namespace fs = std::filesystem;

namespace vpm {
namespace {

const char* kScene = R"(
[render]
width = 8
height = 8
spp = 1
seed = 3
integrator = "photon_map"
[camera]
position = [0.0, 0.0, 4.0]
look_at = [0.0, 0.0, 0.0]
fov = 40
[[lights]]
type = "spot"
position = [-2.0, 3.0, 1.0]
look_at = [0.0, 0.0, 0.0]
intensity = 30.0
cone_angle = 25
[[lights]]
type = "environment"
radiance = [0.02, 0.03, 0.05]
[[media]]
type = "homogeneous"
shape = "sphere"
center = [0.0, 0.0, 0.0]
radius = 1.0
sigma_t_scale = 2.0
albedo = 0.9
g = 0.3
[photons]
count = 400
k = 8
)";

const char* kSweep = R"(scene = "scene.toml"
repeats = 2
[reference]
spp = 8
path_spp = [1]
[axes]
estimator = ["classic", "corrected"]
k = [4, 8]
"media.0.g" = [0.0, 0.5]
)";

class SweepTest : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() /
               ("vpm_sweep_test_" + std::to_string(::getpid()) + "_" +
                ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_);
        std::ofstream(dir_ / "scene.toml") << kScene;
    }
    void TearDown() override { fs::remove_all(dir_); }

    SweepSpec spec(const std::string& text = kSweep) { return parse_sweep(text, "test_sweep.toml", dir_); }

    SweepOutcome run(const SweepPlan& plan, const fs::path& out, int shard = 0, int shards = 1, size_t max_runs = 0) {
        SweepOptions o;
        o.out = out;
        o.shard = shard;
        o.shards = shards;
        o.max_runs = max_runs;
        o.progress = false;
        return run_sweep(plan, o);
    }

    // Rows without the timing and memory columns, keyed by hash (fails on a duplicate hash).
    static std::map<std::string, std::vector<std::string>> rows_of(const fs::path& out) {
        std::map<std::string, std::vector<std::string>> m;
        for (const auto& e : fs::directory_iterator(out)) {
            const std::string n = e.path().filename().string();
            if (n.rfind("runs", 0) != 0 || e.path().extension() != ".csv") continue;
            const CsvTable t = read_csv(e.path());
            EXPECT_FALSE(t.torn_tail) << e.path();
            const int h = t.column("hash");
            std::set<int> skip;
            for (const char* c : {"trace_s", "build_s", "render_s", "total_s", "run_s", "peak_rss_bytes", "image", "reference"})
                skip.insert(t.column(c));
            for (const auto& r : t.rows) {
                std::vector<std::string> kept;
                for (size_t i = 0; i < r.size(); ++i)
                    if (!skip.count(int(i))) kept.push_back(r[i]);
                EXPECT_TRUE(m.emplace(r[size_t(h)], kept).second) << "duplicate row " << r[size_t(h)] << " in " << out;
            }
        }
        return m;
    }

    fs::path dir_;
};

TEST_F(SweepTest, PlanExpandsAxesRepeatsAndPathTracer) {
    const SweepPlan plan = plan_sweep(spec());
    // 2 estimators x 2 k x 2 g photon-map points + 2 path points (one per g), 2 repeats
    ASSERT_EQ(plan.runs.size(), (8u + 2u) * 2u);
    EXPECT_EQ(plan.references.size(), 2u);   // one reference per g
    std::set<std::string> hashes;
    for (const auto& r : plan.runs) hashes.insert(r.hash);
    EXPECT_EQ(hashes.size(), plan.runs.size());
    EXPECT_EQ(plan.runs[0].method, "classic");
    EXPECT_EQ(plan.runs[0].values, (std::vector<std::string>{"classic", "4", "0.0"}));
    EXPECT_EQ(plan.runs[1].method, "path");
    EXPECT_EQ(plan.runs[1].values, (std::vector<std::string>{"", "", "0.0"}));
    EXPECT_EQ(plan.runs.back().repeat, 1);
    EXPECT_EQ(plan.runs.back().stream_offset, 1u);
}

// Issue 15: `kernel` is an axis (photons.kernel) beside `estimator`; the method label carries both,
// and the kernel does not change the scene (one reference, one path-tracer point).
TEST_F(SweepTest, KernelAxisSetsPhotonsKernel) {
    const SweepPlan plan = plan_sweep(spec("scene = \"scene.toml\"\n[reference]\nspp = 4\npath_spp = [1]\n[axes]\n"
                                           "kernel = [\"constant\", \"epanechnikov\", \"cone\"]\n"
                                           "estimator = [\"corrected\"]\nk = [8]\n"));
    EXPECT_EQ(plan.references.size(), 1u);
    std::vector<std::string> methods;
    for (const auto& r : plan.runs) methods.push_back(r.method);
    EXPECT_EQ(methods, (std::vector<std::string>{"corrected", "path", "corrected/epanechnikov", "corrected/cone(slope=1)"}));
}

TEST_F(SweepTest, ResumeAfterRowLimitGivesTheUninterruptedRows) {
    const SweepPlan plan = plan_sweep(spec());
    const auto full = run(plan, dir_ / "full");
    EXPECT_EQ(full.ran, plan.runs.size());

    const fs::path out = dir_ / "resumed";
    EXPECT_EQ(run(plan, out, 0, 1, 3).ran, 3u);
    // a kill inside a row's write leaves a torn last line: it must be dropped, not kept or glued
    { std::ofstream(out / "runs.csv", std::ios::app) << "99,deadbeef,torn"; }
    EXPECT_TRUE(read_csv(out / "runs.csv").torn_tail);
    const auto second = run(plan, out, 0, 1, 5);
    EXPECT_EQ(second.skipped, 3u);
    EXPECT_EQ(second.ran, 5u);
    const auto third = run(plan, out);
    EXPECT_EQ(third.skipped, 8u);
    EXPECT_EQ(third.ran, plan.runs.size() - 8);
    EXPECT_EQ(run(plan, out).ran, 0u);   // nothing left

    const auto a = rows_of(dir_ / "full"), b = rows_of(out);
    EXPECT_EQ(a.size(), plan.runs.size());
    EXPECT_EQ(a, b);   // same hashes, same seeds, same metric values
    EXPECT_EQ(read_csv(out / "points.csv").rows.size(), 10u);
}

TEST_F(SweepTest, UnionOfShardsEqualsTheUnshardedSweep) {
    const SweepPlan plan = plan_sweep(spec());
    run(plan, dir_ / "full");
    size_t total = 0;
    std::vector<fs::path> dirs;
    for (int i = 0; i < 3; ++i) {
        dirs.push_back(dir_ / ("shard" + std::to_string(i)));
        total += run(plan, dirs.back(), i, 3).ran;
    }
    EXPECT_EQ(total, plan.runs.size());
    dirs.push_back(dir_ / "shard1");   // the same folder twice: its rows must not be doubled
    EXPECT_EQ(merge_sweeps(dirs, dir_ / "merged"), plan.runs.size());
    EXPECT_EQ(rows_of(dir_ / "full"), rows_of(dir_ / "merged"));
    // the merged report matches the unsharded one, metric for metric
    const CsvTable p1 = read_csv(dir_ / "full" / "points.csv"), p2 = read_csv(dir_ / "merged" / "points.csv");
    ASSERT_EQ(p1.rows.size(), p2.rows.size());
    for (const char* c : {"point", "rel_rmse", "rel_bias", "rel_bias2", "rel_variance", "nonfinite_pixels"})
        for (size_t i = 0; i < p1.rows.size(); ++i)
            EXPECT_EQ(p1.rows[i][size_t(p1.column(c))], p2.rows[i][size_t(p2.column(c))]) << c;
}

TEST_F(SweepTest, PointsSatisfyTheDecompositionAndAreFinite) {
    const SweepPlan plan = plan_sweep(spec());
    run(plan, dir_ / "full");
    const CsvTable p = read_csv(dir_ / "full" / "points.csv");
    for (const auto& r : p.rows) {
        const double mse = std::stod(r[size_t(p.column("rel_mse"))]);
        const double b2 = std::stod(r[size_t(p.column("rel_bias2"))]);
        const double var = std::stod(r[size_t(p.column("rel_variance"))]);
        EXPECT_NEAR(b2 + var, mse, 1e-8 * mse);
        EXPECT_GT(mse, 0.0);
        EXPECT_EQ(r[size_t(p.column("nonfinite_pixels"))], "0");
        EXPECT_EQ(r[size_t(p.column("repeats"))], "2");
    }
    EXPECT_TRUE(fs::exists(dir_ / "full" / "summary.md"));
    EXPECT_TRUE(fs::exists(dir_ / "full" / "sweep.json"));
}

void expect_plan_error(SweepTest* t, const SweepSpec& s, const std::vector<std::string>& parts) {
    (void)t;
    try {
        plan_sweep(s);
        FAIL() << "no error";
    } catch (const ConfigError& e) {
        const std::string msg = e.what();
        for (const auto& p : parts) EXPECT_NE(msg.find(p), std::string::npos) << "'" << p << "' not in: " << msg;
    }
}

TEST_F(SweepTest, BadAxisKeyOrTypeFailsBeforeAnyWork) {
    const std::string head = "scene = \"scene.toml\"\n[reference]\nspp = 4\n[axes]\nk = [4, 8]\n";
    expect_plan_error(this, spec(head + "\"media.0.gg\" = [0.1]\n"),
                      {"test_sweep.toml:6:", "axes.media.0.gg = 0.1", "unknown key"});
    expect_plan_error(this, spec("scene = \"scene.toml\"\n[reference]\nspp = 4\n[axes]\nk = [4, \"many\"]\n"),
                      {"test_sweep.toml:5:", "axes.k = many", "expected an integer"});
    expect_plan_error(this, spec(head + "\"media.2.g\" = [0.1]\n"), {"axes.media.2.g = 0.1", "past the end"});
    expect_plan_error(this, spec(head + "estimator = [\"fancy\"]\n"), {"axes.estimator = fancy", "allowed"});
    expect_plan_error(this, spec("scene = \"scene.toml\"\n[reference]\nspp = 4\n[axes]\nestimator = [\"mse_optimal\"]\nk = [2]\n"),
                      {"estimator = mse_optimal, k = 2", "k >= 3"});
    // the plan fails before run_sweep could create anything
    EXPECT_FALSE(fs::exists(dir_ / "out"));
    // sweep-file errors name the key and line
    EXPECT_THROW(spec("scene = \"scene.toml\"\nrepeat = 2\n[reference]\nspp = 4\n"), ConfigError);
    EXPECT_THROW(spec("scene = \"scene.toml\"\n[reference]\nspp = 4\nfile = \"x.exr\"\n"), ConfigError);
    EXPECT_THROW(spec("scene = \"missing.toml\"\n[reference]\nspp = 4\n"), ConfigError);
}

TEST(SweepCsv, QuotingRoundTripsAndHeaderMismatchIsRefused) {
    const std::vector<std::string> f = {"a", "b,c", "say \"hi\"", ""};
    std::string line = csv_line(f);
    ASSERT_EQ(line.back(), '\n');
    line.pop_back();
    EXPECT_EQ(parse_csv_line(line), f);
    const fs::path p = fs::temp_directory_path() / ("vpm_sweep_csv_" + std::to_string(::getpid()) + ".csv");
    fs::remove(p);
    prepare_csv(p, {"x", "y"});
    append_csv_row(p, {"1", "2"});
    EXPECT_THROW(prepare_csv(p, {"x", "z"}), FileError);
    { std::ofstream(p, std::ios::app) << "3"; }   // torn
    prepare_csv(p, {"x", "y"});                    // cuts it
    append_csv_row(p, {"4", "5"});
    const CsvTable t = read_csv(p);
    EXPECT_FALSE(t.torn_tail);
    ASSERT_EQ(t.rows.size(), 2u);
    EXPECT_EQ(t.rows[1], (std::vector<std::string>{"4", "5"}));
    fs::remove(p);
}

TEST_F(SweepTest, RowHashFollowsTheResolvedConfigNotItsSpelling) {
    const auto a = RunConfig::build(load_config((dir_ / "scene.toml").string()));
    const auto b = RunConfig::build(load_config((dir_ / "scene.toml").string(), {"photons.max_bounces=1000", "render.output=\"x.exr\""}));
    const auto c = RunConfig::build(load_config((dir_ / "scene.toml").string(), {"photons.k=9"}));
    EXPECT_EQ(run_hash(a.resolved, 3, 0), run_hash(b.resolved, 3, 0));   // explicit default, output path
    EXPECT_NE(run_hash(a.resolved, 3, 0), run_hash(a.resolved, 3, 1));
    EXPECT_NE(run_hash(a.resolved, 3, 0), run_hash(c.resolved, 3, 0));
    EXPECT_EQ(scene_hash(a.resolved), scene_hash(c.resolved));          // photons do not change the reference
    EXPECT_EQ(hash_hex(""), "cbf29ce484222325");                          // FNV-1a offset basis
}

TEST_F(SweepTest, TimeBudgetAxisAppliesToBothMethodsButNotToTheReference) {
    const SweepPlan plan = plan_sweep(spec(R"(scene = "scene.toml"
[reference]
spp = 8
path_spp = [1]
[axes]
time_limit = [0.5, 2]
)"));
    ASSERT_EQ(plan.runs.size(), 4u);   // per budget: one photon-map run, one path run
    int path_runs = 0;
    for (const auto& r : plan.runs) {
        bool has_budget = false;
        for (const auto& o : r.overrides) has_budget |= o.rfind("render.time_limit=", 0) == 0;
        EXPECT_TRUE(has_budget) << r.method;
        path_runs += r.method == "path";
    }
    EXPECT_EQ(path_runs, 2);
    ASSERT_EQ(plan.references.size(), 1u);   // budgets do not change the scene
    for (const auto& o : plan.references.begin()->second) EXPECT_EQ(o.rfind("render.time_limit=", 0), std::string::npos) << o;
}


}  // namespace
}  // namespace vpm

namespace vpm {
namespace {

// Every row says what ran, beside its own sidecar; a photon-map row that ran the path tracer is
// flagged in summary.md and points.csv (the report is recomputed from runs.csv, so editing a row
// stands in for a plan that dropped the map).
TEST_F(SweepTest, RowsSayWhatRanAndTheReportFlagsPhotonMapRowsThatPathTraced) {
    const SweepPlan plan = plan_sweep(spec(R"(scene = "scene.toml"
[reference]
spp = 8
path_spp = [1]
[axes]
k = [4, 8]
)"));
    const fs::path out = dir_ / "out";
    run(plan, out);
    CsvTable t = read_csv(out / "runs.csv");
    const int method = t.column("method"), ran = t.column("integrator_used"), est = t.column("map_estimates"),
              gather = t.column("gather_used"), image = t.column("image"), passes = t.column("passes");
    ASSERT_GE(ran, 0);
    ASSERT_GE(est, 0);
    ASSERT_EQ(t.rows.size(), 3u);
    for (const auto& r : t.rows) {
        const bool path = r[size_t(method)] == "path";
        EXPECT_EQ(r[size_t(ran)], path ? "path" : "photon_map");
        EXPECT_EQ(std::stoull(r[size_t(est)]) > 0, !path) << r[size_t(est)];
        if (path) {
            EXPECT_EQ(r[size_t(gather)], "none");
        }
        EXPECT_EQ(r[size_t(passes)], "1");
        fs::path sidecar = out / r[size_t(image)];
        sidecar.replace_extension(".json");
        std::ifstream in(sidecar);
        ASSERT_TRUE(in) << sidecar;
        const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        EXPECT_NE(text.find("\"integrator_used\": \"" + r[size_t(ran)] + "\""), std::string::npos) << sidecar;
    }
    std::string summary = write_sweep_report(out, {}, "test");
    EXPECT_EQ(summary.find("WARNING"), std::string::npos) << summary;
    EXPECT_NE(summary.find("one repeat (R = 1)"), std::string::npos) << summary;

    // The k = 8 row "ran the path tracer": the report says so.
    for (auto& r : t.rows)
        if (r[size_t(method)] != "path" && r[size_t(t.column("k"))] == "8") r[size_t(ran)] = "path", r[size_t(est)] = "0";
    std::string text = csv_line(t.header);
    for (const auto& r : t.rows) text += csv_line(r);
    std::ofstream(out / "runs.csv") << text;
    summary = write_sweep_report(out, {}, "test");
    EXPECT_NE(summary.find("WARNING: 1 runs of 1 photon-map configurations did not estimate from a photon map"),
              std::string::npos) << summary;
    EXPECT_NE(summary.find("| **path (march)** |"), std::string::npos) << summary;
    const CsvTable points = read_csv(out / "points.csv");
    const int off = points.column("off_plan_repeats");
    ASSERT_GE(off, 0);
    int flagged = 0;
    for (const auto& r : points.rows) flagged += std::stoi(r[size_t(off)]);
    EXPECT_EQ(flagged, 1);
}

}  // namespace
}  // namespace vpm

namespace vpm {
namespace {

// A reference file serves a time_limit axis (a budget does not change the scene), still not an axis
// that does; runs with more camera samples than the reference are named in the summary.
TEST_F(SweepTest, ReferenceFileServesTimeLimitAxesAndRunsOverItsSamplesAreFlagged) {
    const RunConfig ref_config = RunConfig::build(
        load_config((dir_ / "scene.toml").string(), {"render.integrator=\"path\"", "render.spp=1"}));
    RunOptions ro;
    ro.progress = false;
    ro.stream_offset = kReferenceStream;
    RunResult ref = vpm::run(ref_config, ro);
    write_run_outputs(dir_ / "ref.exr", ref, 0.0);
    EXPECT_THROW(spec(R"(scene = "scene.toml"
[reference]
file = "ref.exr"
[axes]
"media.0.g" = [0.0, 0.5]
)"),
                 ConfigError);
    // render.spp = 4 is each pass's samples under the time limit: every run takes >= 4 x 64 > 64 samples.
    const SweepPlan plan = plan_sweep(spec(R"(scene = "scene.toml"
set = ["render.spp=4"]
[reference]
file = "ref.exr"
[axes]
time_limit = [0.02, 0.04]
)"));
    ASSERT_EQ(plan.runs.size(), 2u);
    const fs::path out = dir_ / "out";
    run(plan, out);
    const std::string summary = write_sweep_report(out, {}, "test");
    EXPECT_NE(summary.find("WARNING: 2 runs took more camera samples than their reference"), std::string::npos) << summary;
    const CsvTable t = read_csv(out / "runs.csv");
    for (const auto& r : t.rows) EXPECT_GE(std::stoull(r[size_t(t.column("samples"))]), 256u);
}

}  // namespace
}  // namespace vpm

namespace vpm {
namespace {

// The equal-time section of a summary.
std::string equal_time_section(const std::string& summary) {
    const size_t at = summary.find("## Equal time");
    return at == std::string::npos ? std::string() : summary.substr(at);
}

// A time_limit axis: each budget row holds the runs made for that limit (no empty cell, no run in two
// rows, no "()" label); the report names its metric and the reference's noise floor, which comes from
// the variance image the sweep keeps beside the reference it renders in passes.
TEST_F(SweepTest, EqualTimeRowsHoldEachBudgetsOwnRunsAndTheReportNamesItsMetric) {
    const SweepPlan plan = plan_sweep(spec(R"(scene = "scene.toml"
repeats = 2
[reference]
spp = 8
path_spp = [1]
[axes]
time_limit = [0.02, 0.04]
)"));
    const fs::path out = dir_ / "out";
    run(plan, out);
    ASSERT_EQ(plan.references.size(), 1u);
    EXPECT_TRUE(fs::exists(out / "references" / (plan.references.begin()->first + ".variance.exr")));
    const std::string summary = write_sweep_report(out, {}, "test");
    EXPECT_NE(summary.find("Error: **relMSE**"), std::string::npos) << summary;
    EXPECT_EQ(summary.find("()"), std::string::npos) << summary;
    const std::string table = equal_time_section(summary);
    ASSERT_FALSE(table.empty()) << summary;
    EXPECT_EQ(table.find("–"), std::string::npos) << table;
    for (const char* budget : {"| 0.02 |", "| 0.04 |"}) {
        const size_t row = table.find(budget);
        ASSERT_NE(row, std::string::npos) << table;
        const std::string line = table.substr(row, table.find('\n', row) - row);
        size_t cells = 0;
        for (size_t p = line.find(" at "); p != std::string::npos; p = line.find(" at ", p + 1)) ++cells;
        EXPECT_EQ(cells, 2u) << line;   // the photon map and the path tracer
    }
    const CsvTable points = read_csv(out / "points.csv");
    const int metric = points.column("metric"), floor = points.column("noise_floor"), se = points.column("error_se");
    ASSERT_GE(metric, 0);
    for (const auto& r : points.rows) {
        EXPECT_EQ(r[size_t(metric)], "relMSE");
        EXPECT_GT(std::stod(r[size_t(floor)]), 0.0) << "the reference's variance image gives a floor";
        EXPECT_TRUE(std::isfinite(std::stod(r[size_t(se)]))) << "two repeats give a standard error";
    }
}

// Without a time limit, a run counts at a budget its time fits within to 5%: a 16.0003-s run is a
// 16-s run; one that does not fit leaves its cell empty, and the table says what "–" means.
TEST_F(SweepTest, EqualTimeBudgetsMatchRunTimesWithinATolerance) {
    const SweepPlan plan = plan_sweep(spec(R"(scene = "scene.toml"
[reference]
spp = 8
path_spp = [1]
[axes]
k = [4]
)"));
    const fs::path out = dir_ / "out";
    run(plan, out);
    CsvTable t = read_csv(out / "runs.csv");
    for (auto& r : t.rows) r[size_t(t.column("run_s"))] = "16.0003";
    std::string text = csv_line(t.header);
    for (const auto& r : t.rows) text += csv_line(r);
    std::ofstream(out / "runs.csv") << text;
    std::string table = equal_time_section(write_sweep_report(out, {16.0}, "test"));
    EXPECT_EQ(table.find("–"), std::string::npos) << table;
    EXPECT_EQ(table.find("()"), std::string::npos) << table;
    EXPECT_NE(table.find("(spp=1)"), std::string::npos) << table;
    table = equal_time_section(write_sweep_report(out, {15.0}, "test"));
    EXPECT_NE(table.find("| 15 | – | – |"), std::string::npos) << table;
    EXPECT_NE(table.find("–: no run of that method fits within the budget"), std::string::npos) << table;
    // Another metric, as the sweep file's `metric` sets it.
    MetricOptions smape;
    smape.metric = ErrorMetric::smape;
    EXPECT_NE(write_sweep_report(out, {16.0}, "test", {}, smape).find("Error: **SMAPE**"), std::string::npos);
}

}  // namespace
}  // namespace vpm
