#include "render/run.h"

#include <sstream>

#include <nlohmann/json.hpp>

#include "core/error.h"
#include "core/progress.h"
#include "render/image_io.h"
#include "photon/photon_allocation.h"
#include "photon/photon_budget.h"
#include "photon/photon_map.h"
#include "photon/photon_tracer.h"
#include "render/path_tracer.h"
#include "render/photon_lights_report.h"
#include "render/photon_map_integrator.h"

namespace vpm {

namespace {

nlohmann::json toml_to_json(const toml::table& table) {
    std::ostringstream s;
    s << toml::json_formatter(table);
    return nlohmann::json::parse(s.str());
}

nlohmann::json rgb_json(const Rgb& c) { return nlohmann::json::array({c[0], c[1], c[2]}); }

// The photon pass and the kd-trees (volume map, and the surface map when `surface`), with their
// timings, energy balance and memory in the record. Returns the volume map.
PhotonMap build_volume_photon_map(const Scene& scene, const RunOptions& options, RunRecord& record,
                                  bool surface = false, PhotonMap* surface_map = nullptr) {
    const PhotonSettings& ps = scene.photons;
    PhotonTraceSettings ts;
    ts.count = uint64_t(ps.count);
    ts.seed = scene.render.seed;
    ts.stream_offset = options.stream_offset;
    ts.store_direct = ps.direct == "photon_map";
    ts.max_bounces = ps.max_bounces;
    ts.progress = options.progress;
    ts.store_surface = surface;
    // Stops before the real work when the pilot projects a map that cannot fit; progress lines.
    ts.on_chunk = make_photon_pass_guard(double(physical_memory_bytes()), options.log);
    // Photons per light: by a pilot's importance where the camera looks, or by power.
    const LightAllocation allocation =
        ps.allocation == "importance" ? importance_allocation(scene, ts) : power_allocation(scene);
    ts.light_weights = allocation.weights;
    PhotonTraceResult traced = trace_photons(scene, ts);
    report_photon_lights(scene, allocation, traced, record, options.log);
    record.phase("trace", traced.seconds);
    const size_t stored = traced.photons.size();
    record.set("photons.emitted", traced.paths);
    record.set("photons.stored", uint64_t(stored));
    record.set("photons.collisions", traced.collisions);
    record.set("photons.truncated_paths", traced.truncated_paths);
    record.set("photons.paths_per_second", traced.seconds > 0 ? double(traced.paths) / traced.seconds : 0.0);
    record.set("photons.energy.emitted", rgb_json(traced.energy.emitted));
    record.set("photons.energy.absorbed", rgb_json(traced.energy.absorbed));
    record.set("photons.energy.escaped", rgb_json(traced.energy.escaped));
    record.set("photons.energy.truncated", rgb_json(traced.energy.truncated));
    record.set("photons.energy.relative_imbalance", traced.energy.relative_imbalance());
    if (options.log)
        *options.log << "trace: " << traced.paths << " photon paths, " << traced.collisions << " collisions, "
                      << stored << " stored in " << traced.seconds << " s; energy imbalance "
                      << traced.energy.relative_imbalance() << ", truncated paths " << traced.truncated_paths << "\n";
    // Warn before building a map larger than the budget (records + index, measured per photon).
    const double projected = double(stored + traced.surface_photons.size()) * double(bytes_per_photon() + 4);
    const double budget = ps.memory_budget_fraction * double(physical_memory_bytes());
    record.set("photons.projected_map_bytes", projected);
    record.set("photons.memory_budget_bytes", budget);
    record.set("photons.over_memory_budget", projected > budget);
    if (projected > budget && options.log)
        *options.log << "warning: the photon map will take about " << projected / 1e9 << " GB, over the budget of "
                      << budget / 1e9 << " GB (photons.memory_budget_fraction)\n";

    if (surface) {
        const Timer surface_timer;
        const size_t n_surface = traced.surface_photons.size();
        *surface_map = PhotonMap(traced.surface_photons);
        std::vector<PhotonInput>().swap(traced.surface_photons);
        record.phase("build_surface", surface_timer.seconds());
        record.set("photons.surface_hits", traced.surface_hits);
        record.set("photons.surface_stored", uint64_t(n_surface));
        record.set("photons.surface_map_bytes", uint64_t(surface_map->memory_bytes()));
        if (options.log)
            *options.log << "build: surface photon map, " << traced.surface_hits << " surface hits, " << n_surface
                          << " stored, kd-tree in " << surface_timer.seconds() << " s, "
                          << surface_map->memory_bytes() / 1e6 << " MB\n";
    }

    const Timer build_timer;
    PhotonMap map(traced.photons);
    std::vector<PhotonInput>().swap(traced.photons);
    record.phase("build", build_timer.seconds());
    record.set("photons.bytes_per_photon", uint64_t(bytes_per_photon()));
    record.set("photons.map_bytes", uint64_t(map.memory_bytes()));
    record.set("photons.map_bytes_per_photon", stored ? double(map.memory_bytes()) / double(stored) : 0.0);
    if (options.log)
        *options.log << "build: kd-tree over " << stored << " photons in " << build_timer.seconds() << " s, "
                      << map.memory_bytes() / 1e6 << " MB (" << (stored ? double(map.memory_bytes()) / double(stored) : 0.0)
                      << " bytes/photon)\n";
    return map;
}

}  // namespace

RunResult run_scene(const Scene& scene, const RunOptions& options) {
    RunResult result;
    result.record = RunRecord::with_environment();
    result.record.set("config", toml_to_json(scene.resolved));
    result.record.set("config_file", scene.source_file);
    result.record.set("seed", scene.render.seed);
    result.record.set("integrator", scene.render.integrator);
    result.record.set("build_log", scene.build_log);

    std::unique_ptr<Integrator> integrator;
    PhotonMap map, surface_map;
    if (scene.render.integrator == "path") {
        integrator = std::make_unique<PathTracer>(scene);
    } else {
        const bool surface = scene.uses_embree() && !scene.photons.final_gather;
        if (scene.has_media() || surface) map = build_volume_photon_map(scene, options, result.record, surface, &surface_map);
        else if (options.log) *options.log << "photons: no media and no surface map, so no photon pass\n";
        if (!scene.has_media() && options.log) *options.log << "photons: no media, so the volume photon map is empty\n";
        if (scene.uses_embree() && !surface && options.log)
            *options.log << "photons: final_gather = true, so no surface photon map (paths continue through surfaces)\n";
        integrator = std::make_unique<PhotonMapIntegrator>(scene, map, surface ? &surface_map : nullptr);
    }

    RenderOptions ro;
    ro.width = scene.render.width;
    ro.height = scene.render.height;
    ro.spp = scene.render.spp;
    ro.seed = scene.render.seed;
    ro.progress = options.progress;
    ro.stream_offset = options.stream_offset;
    result.image = render_image(scene.camera, *integrator, ro, result.stats);
    result.record.phase("render", result.stats.seconds);
    result.record.set("render.samples", result.stats.samples);
    result.record.set("render.samples_per_second", result.stats.samples_per_second());
    result.record.set("render.nonfinite_samples", result.stats.nonfinite_samples);
    if (const auto* pm = dynamic_cast<const PhotonMapIntegrator*>(integrator.get())) {
        const EstimatorStats st = pm->stats();
        for (const auto& [name, count] : st.fields()) result.record.set("photons.estimate_cases." + name, count);
        result.record.set("photons.continued_paths", pm->continued_paths());
        if (options.log)
            *options.log << "estimates: " << st.to_string() << "; camera paths continued past a collision "
                         << "(fewer than k photons within photons.max_radius_mfp): " << pm->continued_paths() << "\n";
        const EstimatorStats ss = pm->surface_stats();
        if (ss.queries) {
            for (const auto& [name, count] : ss.fields()) result.record.set("photons.surface_estimate_cases." + name, count);
            if (options.log) *options.log << "surface estimates: " << ss.to_string() << "\n";
        }
    }
    if (options.log) {
        *options.log << "render: " << ro.width << "x" << ro.height << " at " << ro.spp << " spp in "
                      << result.stats.seconds << " s (" << result.stats.samples_per_second() / 1e6
                      << " M samples/s)";
        if (result.stats.nonfinite_samples)
            *options.log << ", " << result.stats.nonfinite_samples << " non-finite samples left out";
        *options.log << "\n";
    }
    return result;
}

void write_run_outputs(const std::filesystem::path& output, RunResult& result, double exposure) {
    const auto folder = output.has_parent_path() ? output.parent_path() : std::filesystem::path(".");
    std::error_code ec;
    std::filesystem::create_directories(folder, ec);
    if (ec) throw FileError(folder.string() + ": cannot create output folder: " + ec.message());
    const Timer timer;
    write_exr(output, result.image);
    write_png_preview(preview_path_for(output), result.image, exposure);
    result.record.phase("write", timer.seconds());
    result.record.set("output.exr", output.string());
    result.record.set("output.png", preview_path_for(output).string());
    result.record.write(sidecar_path_for(output));
}

}  // namespace vpm
