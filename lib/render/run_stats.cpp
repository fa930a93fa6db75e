#include "render/run_stats.h"

#include <nlohmann/json.hpp>

#include "core/progress.h"
#include "render/run_record.h"

namespace vpm {

namespace {

nlohmann::json rgb_json(const Rgb& c) { return nlohmann::json::array({c[0], c[1], c[2]}); }

void write_estimates(const std::string& prefix, const EstimatorStats& st, RunRecord& record) {
    for (const auto& [name, count] : st.fields()) record.set(prefix + name, count);
}

}  // namespace

void RunStats::phase(const std::string& name, double seconds) {
    phases.push_back({name, seconds, peak_rss_bytes()});
}

double RunStats::seconds(const std::string& name) const {
    for (const PhaseStats& p : phases)
        if (p.name == name) return p.seconds;
    return 0.0;
}

void write_run_stats(const RunStats& stats, RunRecord& record) {
    for (const PhaseStats& p : stats.phases) {
        record.set("phases." + p.name + ".seconds", p.seconds);
        record.set("phases." + p.name + ".peak_rss_bytes", p.peak_rss_bytes);
    }
    record.set("render.samples", stats.render.samples);
    record.set("render.samples_per_second", stats.render.samples_per_second());
    record.set("render.nonfinite_samples", stats.render.nonfinite_samples);
    if (const auto& p = stats.photons) {
        record.set("photons.emitted", p->emitted);
        record.set("photons.stored", p->stored);
        record.set("photons.collisions", p->collisions);
        record.set("photons.truncated_paths", p->truncated_paths);
        record.set("photons.paths_per_second", p->paths_per_second);
        record.set("photons.energy.emitted", rgb_json(p->energy.emitted));
        record.set("photons.energy.absorbed", rgb_json(p->energy.absorbed));
        record.set("photons.energy.escaped", rgb_json(p->energy.escaped));
        record.set("photons.energy.truncated", rgb_json(p->energy.truncated));
        record.set("photons.energy.relative_imbalance", p->energy.relative_imbalance());
        record.set("photons.projected_map_bytes", p->projected_map_bytes);
        record.set("photons.memory_budget_bytes", p->memory_budget_bytes);
        record.set("photons.over_memory_budget", p->over_memory_budget);
        record.set("photons.bytes_per_photon", p->bytes_per_photon);
        record.set("photons.map_bytes", p->map_bytes);
        record.set("photons.map_bytes_per_photon", p->map_bytes_per_photon);
        record.set("photons.allocation", p->allocation);
        record.set("photons.stored_per_emitted", p->stored_per_emitted);
        nlohmann::json lights = nlohmann::json::array();
        for (const LightPhotonReport& l : p->lights) {
            const double emitted = double(l.counts.emitted);
            lights.push_back({{"light", l.light},
                              {"weight", l.weight},
                              {"power_share", l.power_share},
                              {"importance", l.importance},
                              {"emitted", l.counts.emitted},
                              {"landed", l.counts.landed},
                              {"stored", l.counts.stored},
                              {"stored_per_emitted", emitted > 0 ? double(l.counts.stored) / emitted : 0.0},
                              {"landed_fraction", emitted > 0 ? double(l.counts.landed) / emitted : 0.0},
                              {"wasted", l.wasted}});
        }
        record.set("photons.lights", lights);
        if (p->surface_map) {
            record.set("photons.surface_hits", p->surface_hits);
            record.set("photons.surface_stored", p->surface_stored);
            record.set("photons.surface_map_bytes", p->surface_map_bytes);
        }
    }
    if (stats.continued_paths) record.set("photons.continued_paths", *stats.continued_paths);
    if (stats.volume_estimates) write_estimates("photons.estimate_cases.", *stats.volume_estimates, record);
    if (stats.surface_estimates) write_estimates("photons.surface_estimate_cases.", *stats.surface_estimates, record);
}

}  // namespace vpm
