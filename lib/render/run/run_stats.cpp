#include "render/run/run_stats.h"

#include <algorithm>
#include <cmath>
#include <ostream>

#include <nlohmann/json.hpp>

#include "core/progress.h"
#include "render/run/run_record.h"

namespace vpm {

void PassSummary::add(const PassStats& p) {
    ++count;
    if (count == 1) {
        spp = p.spp;
        seconds_min = seconds_max = p.seconds;
    }
    seconds_total += p.seconds;
    seconds_min = std::min(seconds_min, p.seconds);
    seconds_max = std::max(seconds_max, p.seconds);
    elapsed = p.elapsed;
    const double d = p.image_mean - image_mean_mean;
    image_mean_mean += d / double(count);
    image_mean_m2 += d * (p.image_mean - image_mean_mean);
}

double PassSummary::image_mean_std() const { return count > 1 ? std::sqrt(image_mean_m2 / double(count - 1)) : 0.0; }

void RunStats::add_pass(const PassStats& p) {
    pass_summary.add(p);
    if (passes.size() < kPassRecords) passes.push_back(p);
}

void RunStats::phase(const std::string& name, double seconds) {
    for (PhaseStats& p : phases)
        if (p.name == name) {
            p.seconds += seconds;
            p.peak_rss_bytes = peak_rss_bytes();
            return;
        }
    phases.push_back({name, seconds, peak_rss_bytes()});
}

double RunStats::seconds(const std::string& name) const {
    for (const PhaseStats& p : phases)
        if (p.name == name) return p.seconds;
    return 0.0;
}

void RunStats::warn(const std::string& message, std::ostream* log) {
    warnings.push_back(message);
    if (log) *log << "warning: " << message << "\n";
}

void write_run_stats(const RunStats& stats, RunRecord& record) {
    for (const PhaseStats& p : stats.phases) {
        record.set("phases." + p.name + ".seconds", p.seconds);
        record.set("phases." + p.name + ".peak_rss_bytes", p.peak_rss_bytes);
    }
    if (const PassSummary& s = stats.pass_summary; s.count > 0) {
        nlohmann::json seconds = nlohmann::json::array(), elapsed = nlohmann::json::array(),
                       means = nlohmann::json::array();
        for (const PassStats& p : stats.passes) {
            seconds.push_back(p.seconds);
            elapsed.push_back(p.elapsed);
            means.push_back(p.image_mean);
        }
        record.set("passes.count", s.count);
        record.set("passes.first", stats.first_pass);
        record.set("passes.spp_per_pass", s.spp);
        // Per pass for the first `recorded` passes only: the sidecar stays small however many passes.
        record.set("passes.recorded", uint64_t(stats.passes.size()));
        record.set("passes.seconds", seconds);
        record.set("passes.elapsed", elapsed);
        record.set("passes.image_mean", means);
        record.set("passes.seconds_total", s.seconds_total);
        record.set("passes.seconds_min", s.seconds_min);
        record.set("passes.seconds_max", s.seconds_max);
        record.set("passes.image_mean_mean", s.image_mean_mean);
        record.set("passes.image_mean_std", s.image_mean_std());
    }
    if (!stats.integrator_used.empty()) record.set("integrator_used", stats.integrator_used);
    if (!stats.warnings.empty()) record.set("warnings", stats.warnings);
    if (stats.gather_used) record.set("gather_used", *stats.gather_used);
    if (stats.map_estimates) record.set("map_estimates", *stats.map_estimates);
    record.set("render.samples", stats.render.samples);
    record.set("render.samples_per_second", stats.render.samples_per_second());
    record.set("render.nonfinite_samples", stats.render.nonfinite_samples);
    record.set("render.negative_samples", stats.render.negative_samples);
    stats.sections.write(record);
}

}  // namespace vpm
