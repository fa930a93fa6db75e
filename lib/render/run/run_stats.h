#pragma once
// The typed statistics of one run. Integrators and the run fill them; analysis code (sweeps,
// the stress matrix, benchmarks) reads them as they are; write_run_stats serialises them into
// the run's JSON record, once, under the keys docs/rendering.md documents.
#include <cstdint>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include "render/run/render_loop.h"
#include "render/run/stats_section.h"

namespace vpm {

class RunRecord;

// Wall time of a phase and the process's peak resident memory when it ended.
struct PhaseStats {
    std::string name;
    double seconds = 0.0;
    uint64_t peak_rss_bytes = 0;
};

// One pass of a run: its photon pass (if any) and its share of the camera samples.
struct PassStats {
    double seconds = 0.0;      // wall time of the pass, all phases
    double elapsed = 0.0;      // since the run started, at the end of the pass
    int spp = 0;
    double image_mean = 0.0;   // mean over pixels and channels of this pass's image alone
};

// Every pass of a run, summarised in constant memory (a time-limited run may make millions).
struct PassSummary {
    uint64_t count = 0;
    int spp = 0;                      // samples per pixel of each pass
    double seconds_total = 0.0, seconds_min = 0.0, seconds_max = 0.0;
    double elapsed = 0.0;             // at the end of the last pass
    double image_mean_mean = 0.0;     // mean over passes of PassStats::image_mean
    double image_mean_m2 = 0.0;       // Welford's sum of squared deviations of it
    void add(const PassStats& p);
    double image_mean_std() const;    // sample standard deviation over passes (0 for one)
};

struct RunStats {
    // Passes are bounded in memory and in the sidecar: `passes` holds the first kPassRecords of
    // them, `pass_summary` all of them (vpm render streams every pass to OUT.passes.csv).
    static constexpr size_t kPassRecords = 256;
    std::vector<PhaseStats> phases;
    std::vector<PassStats> passes;    // the first kPassRecords passes
    PassSummary pass_summary;         // every pass
    int first_pass = 0;   // render.first_pass: passes are first_pass .. first_pass + pass_summary.count - 1
    RenderStats render;
    // What ran (the sidecar's top-level "integrator_used", "gather_used", "map_estimates"): the
    // integrator that rendered ("path" or "photon_map"; for render.integrator = "auto" its plan's
    // choice), the photon map's gather ("collision", "march", "threshold", "beam"; "none" without a
    // map) and the estimates its camera passes took from a map (volume or surface).
    std::string integrator_used;
    std::optional<std::string> gather_used;
    std::optional<uint64_t> map_estimates;
    // The sections the integrator and its gathers keep (render/run/stats_section.h).
    StatsSections sections;
    // What the run could not honour and went on with (the sidecar's "warnings", also logged).
    std::vector<std::string> warnings;
    // Keeps `message` in warnings and writes "warning: message" on log (when given).
    void warn(const std::string& message, std::ostream* log);

    // Counts a pass in the summary and keeps its record while fewer than kPassRecords are kept.
    void add_pass(const PassStats& p);
    uint64_t pass_count() const { return pass_summary.count; }
    // Adds `seconds` to a phase (phases repeat once per pass), with the peak resident memory now.
    void phase(const std::string& name, double seconds);
    // Seconds of a phase; 0 when the run had no such phase.
    double seconds(const std::string& name) const;
};

// Writes every statistic into `record` (phases.*, passes.*, render.*, and each section's keys).
void write_run_stats(const RunStats& stats, RunRecord& record);

}  // namespace vpm
