#include "render/run/run_stats.h"

#include <algorithm>
#include <cmath>
#include <ostream>

#include <nlohmann/json.hpp>

#include "core/progress.h"
#include "render/run/run_record.h"

namespace vpm {

namespace {

nlohmann::json rgb_json(const Rgb& c) { return nlohmann::json::array({c[0], c[1], c[2]}); }

void write_estimates(const std::string& prefix, const EstimatorStats& st, RunRecord& record) {
    for (const auto& [name, count] : st.fields()) record.set(prefix + name, count);
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

void RunStats::add_photon_pass(const PhotonPassStats& p) {
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
    if (const auto& l = stats.photon_ledger) {
        record.set("photons.traced.pass_maps", l->pass_maps);
        record.set("photons.traced.passes", l->passes_traced);
        record.set("photons.traced.estimates", l->estimates);
        record.set("photons.traced.pilot_only", l->pilot_only);
        record.set("photons.traced.probe", l->probe);
        record.set("photons.traced.decision_map", l->decision_map);
        record.set("photons.traced.decision_queries", l->decision_queries);
    }
    record.set("render.samples", stats.render.samples);
    record.set("render.samples_per_second", stats.render.samples_per_second());
    record.set("render.nonfinite_samples", stats.render.nonfinite_samples);
    record.set("render.negative_samples", stats.render.negative_samples);
    if (const auto& p = stats.photons) {
        record.set("photons.emitted", p->emitted);
        record.set("photons.stored", p->stored);
        record.set("photons.collisions", p->collisions);
        record.set("photons.storing_walks", p->storing_walks);
        record.set("photons.store_probability_used", p->store_probability);
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
                              {"wasted", l.wasted}, {"reaches_nothing", l.reaches_nothing}});
        }
        record.set("photons.lights", lights);
        if (p->surface_map) {
            record.set("photons.surface_hits", p->surface_hits);
            record.set("photons.surface_stored", p->surface_stored);
            record.set("photons.surface_map_bytes", p->surface_map_bytes);
        }
    }
    if (stats.continued_paths) record.set("photons.continued_paths", *stats.continued_paths);
    if (stats.linear_fallbacks) record.set("photons.linear_fallbacks", *stats.linear_fallbacks);
    if (stats.decision_queries) record.set("photons.decision_queries", *stats.decision_queries);
    if (stats.decision_map_photons) record.set("photons.decision_map_photons", *stats.decision_map_photons);
    if (stats.march_wide_queries) record.set("photons.march_wide_queries", *stats.march_wide_queries);
    if (stats.march_weight_max) record.set("photons.march_weight_max", *stats.march_weight_max);
    if (stats.march_weight_mean) record.set("photons.march_weight_mean", *stats.march_weight_mean);
    if (const auto& r = stats.pass_radii) {
        record.set("photons.radii.schedule", r->schedule);
        record.set("photons.radii.alpha_points", r->alpha_points);
        record.set("photons.radii.alpha_surfaces", r->alpha_surfaces);
        nlohmann::json pass = nlohmann::json::array(), k = nlohmann::json::array(), vs = nlohmann::json::array(),
                       ss = nlohmann::json::array(), bs = nlohmann::json::array();
        for (size_t i = 0; i < r->radii.size(); ++i) {
            pass.push_back(r->pass[i]);
            k.push_back(r->radii[i].k);
            vs.push_back(r->radii[i].volume_scale);
            ss.push_back(r->radii[i].surface_scale);
            bs.push_back(r->radii[i].beam_scale);
        }
        record.set("photons.radii.pass", pass);
        record.set("photons.radii.k", k);
        record.set("photons.radii.volume_scale", vs);
        record.set("photons.radii.surface_scale", ss);
        record.set("photons.radii.beam_scale", bs);
        record.set("photons.radii.last_pass", r->last_pass);
        record.set("photons.radii.last_k", r->last.k);
        record.set("photons.radii.last_volume_scale", r->last.volume_scale);
        record.set("photons.radii.last_surface_scale", r->last.surface_scale);
        record.set("photons.radii.last_beam_scale", r->last.beam_scale);
    }
    if (const auto& b = stats.photon_beams) {
        record.set("photons.photon_beams.widths", b->widths);
        record.set("photons.photon_beams.k", b->k);
        record.set("photons.photon_beams.recorded", b->recorded);
        record.set("photons.photon_beams.beams", b->beams);
        record.set("photons.photon_beams.pieces", b->pieces);
        record.set("photons.photon_beams.piece_length", b->piece_length);
        record.set("photons.photon_beams.bvh_bytes", b->bvh_bytes);
        record.set("photons.photon_beams.bytes_per_beam", b->bytes_per_beam);
        record.set("photons.photon_beams.widths_seconds", b->widths_seconds);
        record.set("photons.photon_beams.widths_tested", b->widths_tested);
        record.set("photons.photon_beams.bvh_seconds", b->bvh_seconds);
        record.set("photons.photon_beams.queries", b->queries);
        record.set("photons.photon_beams.crossed", b->crossed);
        record.set("photons.photon_beams.tested", b->tested);
        record.set("photons.photon_beams.starved", b->starved);
        record.set("photons.photon_beams.band_zeros", b->band_zeros);
        record.set("photons.photon_beams.widths_bounded", b->widths_bounded);
        record.set("photons.photon_beams.widths_extrapolated", b->widths_extrapolated);
        record.set("photons.photon_beams.widths_typical", b->widths_typical);
        record.set("photons.photon_beams.beams_left_out", b->beams_left_out);
        record.set("photons.photon_beams.tracking_lookups", b->tracking_lookups);
    }
    if (const auto& b = stats.beam) {
        record.set("photons.beam.k", b->k);
        record.set("photons.beam.photons", b->photons);
        record.set("photons.beam.bvh_bytes", b->bvh_bytes);
        record.set("photons.beam.bvh_bytes_per_photon", b->bvh_bytes_per_photon);
        record.set("photons.beam.map_bytes_per_photon", b->map_bytes_per_photon);
        record.set("photons.beam.total_bytes_per_photon", b->total_bytes_per_photon);
        record.set("photons.beam.radii_seconds", b->radii_seconds);
        record.set("photons.beam.bvh_seconds", b->bvh_seconds);
        record.set("photons.beam.queries", b->queries);
        record.set("photons.beam.crossed", b->crossed);
        record.set("photons.beam.tracking_lookups", b->tracking_lookups);
    }
    if (const auto& g = stats.gather_pilot) {
        record.set("photons.gather_pilot.chosen", g->chosen);
        record.set("photons.gather_pilot.candidates", nlohmann::json(g->candidates));
        record.set("photons.gather_pilot.variance", nlohmann::json(g->variance));
        record.set("photons.gather_pilot.cost", nlohmann::json(g->cost));
        record.set("photons.gather_pilot.chosen_count", nlohmann::json(g->chosen_count));
    }
    if (const auto& a = stats.auto_gather) {
        record.set("photons.auto_gather.chosen", a->chosen);
        std::vector<std::string> names;
        std::vector<double> v_camera, v_map_half, v_map_half_se, v_map_quarter, bias2, bias_mean, bias_se, weights, means, mean_ses, tails, v_camera_rel_se, cost, queries, rays, lookups, used, steps, density_lookups, cells;
        std::vector<int> samples;
        std::vector<bool> dropped, excluded;
        for (const auto& c : a->candidates) {
            names.push_back(c.name);
            v_camera.push_back(c.v_camera);
            v_map_half.push_back(c.v_map_half);
            v_map_half_se.push_back(c.v_map_half_se);
            v_map_quarter.push_back(c.v_map_quarter);
            cost.push_back(c.sample_cost);
            bias2.push_back(c.bias2);
            bias_mean.push_back(c.bias_mean);
            bias_se.push_back(c.bias_se);
            weights.push_back(c.max_weight);
            means.push_back(c.mean);
            mean_ses.push_back(c.mean_se);
            tails.push_back(c.tail_share);
            v_camera_rel_se.push_back(c.v_camera_rel_se);
            queries.push_back(c.per_sample.queries);
            rays.push_back(c.per_sample.rays);
            lookups.push_back(c.per_sample.lookups);
            used.push_back(c.per_sample.map_used);
            steps.push_back(c.per_sample.steps);
            density_lookups.push_back(c.per_sample.density_lookups);
            cells.push_back(c.per_sample.cells);
            samples.push_back(c.samples);
            dropped.push_back(c.dropped);
            excluded.push_back(c.excluded);
        }
        record.set("photons.auto_gather.candidates", nlohmann::json(names));
        record.set("photons.auto_gather.v_camera", nlohmann::json(v_camera));
        record.set("photons.auto_gather.v_map_half", nlohmann::json(v_map_half));
        record.set("photons.auto_gather.v_map_half_se", nlohmann::json(v_map_half_se));
        record.set("photons.auto_gather.v_map_quarter", nlohmann::json(v_map_quarter));
        record.set("photons.auto_gather.sample_cost", nlohmann::json(cost));
        record.set("photons.auto_gather.bias2", nlohmann::json(bias2));
        record.set("photons.auto_gather.bias_mean", nlohmann::json(bias_mean));
        record.set("photons.auto_gather.bias_se", nlohmann::json(bias_se));
        record.set("photons.auto_gather.march_weight_max", nlohmann::json(weights));
        record.set("photons.auto_gather.mean", nlohmann::json(means));
        record.set("photons.auto_gather.mean_se", nlohmann::json(mean_ses));
        record.set("photons.auto_gather.tail_share", nlohmann::json(tails));
        record.set("photons.auto_gather.v_camera_rel_se", nlohmann::json(v_camera_rel_se));
        record.set("photons.auto_gather.queries_per_sample", nlohmann::json(queries));
        record.set("photons.auto_gather.rays_per_sample", nlohmann::json(rays));
        record.set("photons.auto_gather.lookups_per_sample", nlohmann::json(lookups));
        record.set("photons.auto_gather.map_used_per_sample", nlohmann::json(used));
        record.set("photons.auto_gather.steps_per_sample", nlohmann::json(steps));
        record.set("photons.auto_gather.density_lookups_per_sample", nlohmann::json(density_lookups));
        record.set("photons.auto_gather.cells_per_sample", nlohmann::json(cells));
        record.set("photons.auto_gather.pilot_samples", nlohmann::json(samples));
        record.set("photons.auto_gather.dropped", nlohmann::json(dropped));
        record.set("photons.auto_gather.excluded", nlohmann::json(excluded));
        record.set("photons.auto_gather.photon_pass", a->photon_pass);
        nlohmann::json score = nlohmann::json::array();
        for (double v : a->score) score.push_back(std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr));
        record.set("photons.auto_gather.score", score);
        record.set("photons.auto_gather.photon_cost", a->photon_cost);
        record.set("photons.auto_gather.pilot_count", a->pilot_count);
        record.set("photons.auto_gather.count", a->count);
        record.set("photons.auto_gather.spp", a->spp);
        record.set("photons.auto_gather.beta", a->beta);
        record.set("photons.auto_gather.beta_measured", a->beta_measured);
        record.set("photons.auto_gather.size_photons", a->size_photons);
        record.set("photons.auto_gather.size_samples", a->size_samples);
    }
    if (stats.volume_estimates) write_estimates("photons.estimate_cases.", *stats.volume_estimates, record);
    if (stats.surface_estimates) write_estimates("photons.surface_estimate_cases.", *stats.surface_estimates, record);
}

}  // namespace vpm
