#include "render/photon_map/photon_map_stats.h"

#include <algorithm>
#include <cmath>

#include <nlohmann/json.hpp>

#include "render/run/run_record.h"

namespace vpm {

namespace {

nlohmann::json rgb_json(const Rgb& c) { return nlohmann::json::array({c[0], c[1], c[2]}); }

// photons.auto_gather.KEY: one value of type T per candidate of the plan.
template <class T, class Value>
void write_per_candidate(const std::vector<GatherMeasurement>& candidates, const char* key, Value value,
                         RunRecord& record) {
    std::vector<T> values;
    for (const GatherMeasurement& m : candidates) values.push_back(T(value(m)));
    record.set(std::string("photons.auto_gather.") + key, nlohmann::json(values));
}

void write_estimates(const std::string& prefix, const EstimatorStats& st, RunRecord& record) {
    for (const auto& [name, count] : st.fields()) record.set(prefix + name, count);
}

// photons.traced.*: the photons traced per phase
void write_ledger(const PhotonLedger& l, RunRecord& record) {
    record.set("photons.traced.pass_maps", l.pass_maps);
    record.set("photons.traced.passes", l.passes_traced);
    record.set("photons.traced.estimates", l.estimates);
    record.set("photons.traced.pilot_only", l.pilot_only);
    record.set("photons.traced.probe", l.probe);
    record.set("photons.traced.decision_map", l.decision_map);
    record.set("photons.traced.decision_queries", l.decision_queries);
}

// photons.*: the photon passes' counts, energy, memory and lights
void write_photon_pass(const PhotonPassStats& p, RunRecord& record) {
    record.set("photons.emitted", p.emitted);
    record.set("photons.stored", p.stored);
    record.set("photons.collisions", p.collisions);
    record.set("photons.storing_walks", p.storing_walks);
    record.set("photons.store_probability_used", p.store_probability);
    record.set("photons.truncated_paths", p.truncated_paths);
    record.set("photons.paths_per_second", p.paths_per_second);
    record.set("photons.energy.emitted", rgb_json(p.energy.emitted));
    record.set("photons.energy.absorbed", rgb_json(p.energy.absorbed));
    record.set("photons.energy.escaped", rgb_json(p.energy.escaped));
    record.set("photons.energy.truncated", rgb_json(p.energy.truncated));
    record.set("photons.energy.relative_imbalance", p.energy.relative_imbalance());
    record.set("photons.projected_map_bytes", p.projected_map_bytes);
    record.set("photons.memory_budget_bytes", p.memory_budget_bytes);
    record.set("photons.over_memory_budget", p.over_memory_budget);
    record.set("photons.bytes_per_photon", p.bytes_per_photon);
    record.set("photons.map_bytes", p.map_bytes);
    record.set("photons.map_bytes_per_photon", p.map_bytes_per_photon);
    record.set("photons.allocation", p.allocation);
    record.set("photons.stored_per_emitted", p.stored_per_emitted);
    nlohmann::json lights = nlohmann::json::array();
    for (const LightPhotonReport& l : p.lights) {
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
                          {"wasted", l.wasted}, {"reaches_nothing", l.reaches_nothing}});
    }
    record.set("photons.lights", lights);
    if (p.surface_map) {
        record.set("photons.surface_hits", p.surface_hits);
        record.set("photons.surface_stored", p.surface_stored);
        record.set("photons.surface_map_bytes", p.surface_map_bytes);
    }
}

// photons.radii.*: k and the radius scales per recorded pass
void write_pass_radii(const PassRadiiStats& r, RunRecord& record) {
    record.set("photons.radii.schedule", r.schedule);
    record.set("photons.radii.alpha_points", r.alpha_points);
    record.set("photons.radii.alpha_surfaces", r.alpha_surfaces);
    nlohmann::json pass = nlohmann::json::array(), k = nlohmann::json::array(), vs = nlohmann::json::array(),
                   ss = nlohmann::json::array(), bs = nlohmann::json::array();
    for (size_t i = 0; i < r.radii.size(); ++i) {
        pass.push_back(r.pass[i]);
        k.push_back(r.radii[i].k);
        vs.push_back(r.radii[i].volume_scale);
        ss.push_back(r.radii[i].surface_scale);
        bs.push_back(r.radii[i].beam_scale);
    }
    record.set("photons.radii.pass", pass);
    record.set("photons.radii.k", k);
    record.set("photons.radii.volume_scale", vs);
    record.set("photons.radii.surface_scale", ss);
    record.set("photons.radii.beam_scale", bs);
    record.set("photons.radii.last_pass", r.last_pass);
    record.set("photons.radii.last_k", r.last.k);
    record.set("photons.radii.last_volume_scale", r.last.volume_scale);
    record.set("photons.radii.last_surface_scale", r.last.surface_scale);
    record.set("photons.radii.last_beam_scale", r.last.beam_scale);
}

// photons.gather_pilot.*
void write_gather_pilot(const GatherPilotStats& g, RunRecord& record) {
    record.set("photons.gather_pilot.chosen", g.chosen);
    record.set("photons.gather_pilot.candidates", nlohmann::json(g.candidates));
    record.set("photons.gather_pilot.variance", nlohmann::json(g.variance));
    record.set("photons.gather_pilot.cost", nlohmann::json(g.cost));
    record.set("photons.gather_pilot.chosen_count", nlohmann::json(g.chosen_count));
}

// photons.auto_gather.*: the plan's candidates, measurements and choice
void write_auto_gather(const AutoGatherStats& a, RunRecord& record) {
    record.set("photons.auto_gather.chosen", a.chosen);
    using M = GatherMeasurement;
    const std::vector<M>& c = a.candidates;
    write_per_candidate<std::string>(c, "candidates", [](const M& m) { return m.name; }, record);
    write_per_candidate<double>(c, "v_camera", [](const M& m) { return m.v_camera; }, record);
    write_per_candidate<double>(c, "v_map_half", [](const M& m) { return m.v_map_half; }, record);
    write_per_candidate<double>(c, "v_map_half_se", [](const M& m) { return m.v_map_half_se; }, record);
    write_per_candidate<double>(c, "v_map_quarter", [](const M& m) { return m.v_map_quarter; }, record);
    write_per_candidate<double>(c, "sample_cost", [](const M& m) { return m.sample_cost; }, record);
    write_per_candidate<double>(c, "bias2", [](const M& m) { return m.bias2; }, record);
    write_per_candidate<double>(c, "bias_mean", [](const M& m) { return m.bias_mean; }, record);
    write_per_candidate<double>(c, "bias_se", [](const M& m) { return m.bias_se; }, record);
    write_per_candidate<double>(c, "march_weight_max", [](const M& m) { return m.max_weight; }, record);
    write_per_candidate<double>(c, "mean", [](const M& m) { return m.mean; }, record);
    write_per_candidate<double>(c, "mean_se", [](const M& m) { return m.mean_se; }, record);
    write_per_candidate<double>(c, "tail_share", [](const M& m) { return m.tail_share; }, record);
    write_per_candidate<double>(c, "v_camera_rel_se", [](const M& m) { return m.v_camera_rel_se; }, record);
    write_per_candidate<double>(c, "queries_per_sample", [](const M& m) { return m.per_sample.queries; }, record);
    write_per_candidate<double>(c, "rays_per_sample", [](const M& m) { return m.per_sample.rays; }, record);
    write_per_candidate<double>(c, "lookups_per_sample", [](const M& m) { return m.per_sample.lookups; }, record);
    write_per_candidate<double>(c, "map_used_per_sample", [](const M& m) { return m.per_sample.map_used; }, record);
    write_per_candidate<double>(c, "steps_per_sample", [](const M& m) { return m.per_sample.steps; }, record);
    write_per_candidate<double>(c, "density_lookups_per_sample", [](const M& m) { return m.per_sample.density_lookups; }, record);
    write_per_candidate<double>(c, "cells_per_sample", [](const M& m) { return m.per_sample.cells; }, record);
    write_per_candidate<int>(c, "pilot_samples", [](const M& m) { return m.samples; }, record);
    write_per_candidate<bool>(c, "dropped", [](const M& m) { return m.dropped; }, record);
    write_per_candidate<bool>(c, "excluded", [](const M& m) { return m.excluded; }, record);
    write_per_candidate<bool>(c, "stopped_early", [](const M& m) { return m.stopped_early; }, record);
    write_per_candidate<double>(c, "stop_low_score", [](const M& m) { return m.stop_low_score; }, record);
    write_per_candidate<double>(c, "stop_best_map_score", [](const M& m) { return m.stop_best_map_score; }, record);
    record.set("photons.auto_gather.photon_pass", a.photon_pass);
    nlohmann::json score = nlohmann::json::array();
    for (double v : a.score) score.push_back(std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr));
    record.set("photons.auto_gather.score", score);
    record.set("photons.auto_gather.photon_cost", a.photon_cost);
    record.set("photons.auto_gather.pilot_work", a.pilot_work);
    record.set("photons.auto_gather.pilot_count", a.pilot_count);
    record.set("photons.auto_gather.count", a.count);
    record.set("photons.auto_gather.spp", a.spp);
    record.set("photons.auto_gather.beta", a.beta);
    record.set("photons.auto_gather.beta_measured", a.beta_measured);
    record.set("photons.auto_gather.size_photons", a.size_photons);
    record.set("photons.auto_gather.size_samples", a.size_samples);
}

}  // namespace

void PhotonPassStats::merge(const PhotonPassStats& o) {
    emitted += o.emitted;
    stored += o.stored;
    collisions += o.collisions;
    storing_walks += o.storing_walks;
    store_probability = o.store_probability;
    truncated_paths += o.truncated_paths;
    energy.emitted += o.energy.emitted;
    energy.absorbed += o.energy.absorbed;
    energy.escaped += o.energy.escaped;
    energy.truncated += o.energy.truncated;
    projected_map_bytes = std::max(projected_map_bytes, o.projected_map_bytes);
    memory_budget_bytes = o.memory_budget_bytes;
    over_memory_budget = over_memory_budget || o.over_memory_budget;
    bytes_per_photon = o.bytes_per_photon;
    map_bytes = std::max(map_bytes, o.map_bytes);
    surface_map = surface_map || o.surface_map;
    surface_hits += o.surface_hits;
    surface_stored += o.surface_stored;
    surface_map_bytes = std::max(surface_map_bytes, o.surface_map_bytes);
    allocation = o.allocation;
    stored_per_emitted = emitted ? double(stored + surface_stored) / double(emitted) : 0.0;
    if (lights.size() == o.lights.size()) {   // the allocation pilot runs per pass: counts add
        for (size_t l = 0; l < lights.size(); ++l) {
            lights[l].counts.emitted += o.lights[l].counts.emitted;
            lights[l].counts.landed += o.lights[l].counts.landed;
            lights[l].counts.stored += o.lights[l].counts.stored;
            lights[l].wasted = lights[l].wasted || o.lights[l].wasted;
            lights[l].reaches_nothing = lights[l].reaches_nothing || o.lights[l].reaches_nothing;
        }
    }
}

void PhotonMapStats::add_photon_pass(const PhotonPassStats& p) {
    if (!photons) {
        photons = p;
        return;
    }
    // Rates and per-photon bytes are recomputed from the sums.
    const double seconds_before = photons->paths_per_second > 0 ? double(photons->emitted) / photons->paths_per_second : 0.0;
    const double seconds_now = p.paths_per_second > 0 ? double(p.emitted) / p.paths_per_second : 0.0;
    photons->merge(p);
    const double seconds = seconds_before + seconds_now;
    photons->paths_per_second = seconds > 0 ? double(photons->emitted) / seconds : 0.0;
    photons->map_bytes_per_photon = p.map_bytes_per_photon;
}

const PhotonMapStats& PhotonMapStats::of(const RunStats& run) {
    static const PhotonMapStats none;
    const PhotonMapStats* s = run.sections.find<PhotonMapStats>();
    return s ? *s : none;
}

void PhotonMapStats::write(RunRecord& record) const {
    if (photon_ledger) write_ledger(*photon_ledger, record);
    if (photons) write_photon_pass(*photons, record);
    if (continued_paths) record.set("photons.continued_paths", *continued_paths);
    if (linear_fallbacks) record.set("photons.linear_fallbacks", *linear_fallbacks);
    if (linear_negatives) record.set("photons.linear_negative_estimates", *linear_negatives);
    if (decision_queries) record.set("photons.decision_queries", *decision_queries);
    if (decision_map_photons) record.set("photons.decision_map_photons", *decision_map_photons);
    if (march_wide_queries) record.set("photons.march_wide_queries", *march_wide_queries);
    if (march_weight_max) record.set("photons.march_weight_max", *march_weight_max);
    if (march_weight_mean) record.set("photons.march_weight_mean", *march_weight_mean);
    if (pass_radii) write_pass_radii(*pass_radii, record);
    if (gather_pilot) write_gather_pilot(*gather_pilot, record);
    if (auto_gather) write_auto_gather(*auto_gather, record);
    if (volume_estimates) write_estimates("photons.estimate_cases.", *volume_estimates, record);
    if (surface_estimates) write_estimates("photons.surface_estimate_cases.", *surface_estimates, record);
}

}  // namespace vpm
