#pragma once
// Running a sweep plan and reporting it.
//
// Output folder layout (--out):
//   runs.csv | runs.shard-I-of-N.csv   one row per finished run (appended, fsynced; see sweep_csv.h)
//   images/<run hash>.exr              each run's image (atomic), so repeats can be compared later
//   images/<run hash>.json             each run's sidecar (what ran, its plan, every statistic)
//   references/<scene hash>.exr/.json  rendered references (path tracer), cached by scene hash
//   points.csv                         one row per configuration: metrics over its repeats
//   summary.md                         points table and equal-time table
//   sweep.json                         sidecar: environment, sweep file, plan, counts, timings
//   error_vs_time, error_vs_k, bias_vs_k .png/.pdf/.svg   (tools/plot_sweep.py, when available)
// The report (points.csv, summary.md, plots) is always recomputed from every runs*.csv row in
// the folder and the images, so it is the same whether the runs came in one go, resumed, or from
// shards merged with merge_sweeps.
#include <cstddef>
#include <filesystem>
#include <functional>
#include <set>
#include <string>
#include <vector>

#include "analysis/metrics/error_metrics.h"
#include "analysis/sweep/sweep_plan.h"

namespace vpm {

struct SweepOptions {
    std::filesystem::path out = "out/sweep";
    int shard = 0, shards = 1;     // this process runs plan runs with index % shards == shard
    int jobs = 1;                  // runs at once (each run is itself multi-threaded)
    size_t max_runs = 0;           // stop after this many new runs (0: all); simulates a kill
    bool references_only = false; // render every missing reference of the whole plan, run nothing
    bool progress = true;          // progress bars of reference renders
    std::vector<std::string> command_line;
    std::function<void(const std::string&)> log;   // progress lines (may be empty)
    // Polled before and after every run and reference (may be empty): once true, nothing more is
    // written (a run that was under way is dropped, as if killed) and run_sweep returns without
    // the report. The Python module's Ctrl-C; a rerun resumes.
    std::function<bool()> cancelled;
};

struct SweepOutcome {
    size_t planned = 0, in_shard = 0, skipped = 0, ran = 0, remaining = 0;
    double seconds = 0;
    std::filesystem::path csv;
};

// Renders missing references, runs the shard's unfinished runs, then writes the report.
SweepOutcome run_sweep(const SweepPlan& plan, const SweepOptions& options);

// Fixed columns of runs.csv around the axis columns.
std::vector<std::string> sweep_csv_header(const std::vector<SweepAxis>& axes);
std::filesystem::path shard_csv_name(int shard, int shards);

// Recomputes points.csv and summary.md from the folder's rows; returns the summary Markdown.
// budgets: equal-time budgets in seconds (empty: the time_limit axis's values, else three
// log-spaced from the measured times).
// only: when not empty, rows whose hash is not in it are left out (rows of an edited sweep file
// that are no longer in the plan stay in runs.csv but not in the report).
// metric: the report's error (summary.md, points.csv's error columns, the equal-time table).
std::string write_sweep_report(const std::filesystem::path& out, const std::vector<double>& budgets,
                               const std::string& title, const std::set<std::string>& only = {},
                               const MetricOptions& metric = {});

// Merges the runs*.csv of `dirs` into out/runs.csv (duplicates by hash dropped; image and reference
// paths rewritten relative to `out`), copies sweep.json from the first folder that has one, and
// writes the report. Returns the number of rows.
size_t merge_sweeps(const std::vector<std::filesystem::path>& dirs, const std::filesystem::path& out,
                    const std::function<void(const std::string&)>& log = {});

// Runs `script` (tools/plot_sweep.py) on the folder with /usr/bin/python3; false (and a log line
// saying why) when python3, the script or matplotlib is missing: plotting is optional.
bool plot_sweep(const std::filesystem::path& out, const std::filesystem::path& script,
                const std::function<void(const std::string&)>& log);

}  // namespace vpm
