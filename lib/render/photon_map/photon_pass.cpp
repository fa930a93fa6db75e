#include "render/photon_map/photon_pass.h"

#include <algorithm>
#include <cmath>
#include <ostream>

#include <tbb/task_group.h>

#include "core/progress.h"
#include "core/sampling/rng.h"
#include "core/sampling/sampler_registry.h"
#include "photon/trace/photon_allocation.h"
#include "photon/trace/photon_budget.h"
#include "render/photon_map/photon_lights_report.h"
#include "render/plan/pass_plan.h"
#include "render/plan/pilot_budget.h"

namespace vpm {

namespace {

// The pass's trace settings, with the photons per light of the run (computed on the first call).
PhotonTraceSettings trace_settings(const Scene& scene, const PhotonMapSettings& ps, const PassContext& context,
                                   bool surface, std::optional<LightAllocation>& cached) {
    PhotonTraceSettings ts;
    ts.count = uint64_t(ps.count);
    ts.seed = context.seed;
    ts.stream_offset = context.stream_offset;
    ts.store_direct = ps.direct == DirectLighting::photon_map;
    ts.max_bounces = ps.max_bounces;
    ts.progress = context.progress;
    ts.store_surface = surface;
    ts.store_probability = ps.store_probability;
    ts.store_auto = ps.store_auto;
    ts.forced_collisions = ps.forced_collisions;
    ts.sampler = ps.sampler;
    ts.store_beams = ps.gather == GatherMode::photon_beams;
    ts.store_volume = !ts.store_beams;
    // Photons per light: by a pilot's importance where the camera looks, or by power.
    if (!cached) {
        PhotonTraceSettings pilot = ts;
        pilot.stream_offset = context.run_stream_offset;
        pilot.store_beams = false;   // the allocation as every gather's
        pilot.store_volume = true;
        cached = ps.allocation == PhotonAllocationRule::importance ? importance_allocation(scene, pilot) : power_allocation(scene);
    }
    ts.light_weights = cached->weights;
    return ts;
}

}  // namespace

PilotPhotonCount pilot_photon_count(const Scene& scene, const PhotonMapSettings& ps, const PassContext& context,
                                    bool surface_map, std::optional<LightAllocation>& allocation) {
    PilotPhotonCount p;
    p.count = ps.count;
    // The run's allocation, as its passes would compute it (with their surface map), then volume only.
    PhotonTraceSettings probe = trace_settings(scene, ps, context, surface_map, allocation);
    probe.store_surface = false;
    probe.count = std::min<uint64_t>(kPilotProbePhotons, uint64_t(ps.count));
    probe.seed = mix64(context.seed ^ 0x70726f6265ULL);   // apart from every pass's map
    probe.stream_offset = context.run_stream_offset;
    probe.progress = false;
    const PhotonTraceResult traced = trace_photons(scene, probe);
    p.probe_photons = int64_t(traced.paths);
    p.stored_per_photon = traced.paths ? double(traced.photons.size()) / double(traced.paths) : 0.0;
    p.collisions_per_photon = traced.paths ? double(traced.collisions) / double(traced.paths) : 0.0;
    // A multiple of the probe's photons near `wanted`, within [probe, photons.count].
    auto probes = [&](double wanted) {
        return std::min(ps.count, std::max(kPilotProbePhotons, int64_t(std::ceil(wanted / double(kPilotProbePhotons))) * kPilotProbePhotons));
    };
    if (p.stored_per_photon * double(ps.count) > kPilotStoredPhotons) p.count = probes(kPilotStoredPhotons / p.stored_per_photon);
    if (ps.time_limit > 0.0) {
        const double most = kPilotBudgetFraction * ps.time_limit * kWorkUnitsPerSecond / photon_units(work_units(scene, ps.k), p);
        // (A limit whose share cannot hold the probe's photons is no guide to the pilot's size.)
        if (double(p.count) > most && most >= double(kPilotProbePhotons) && probes(most) < p.count) {
            p.count = probes(most);
            p.held_by_limit = true;
        }
    }
    return p;
}

double photon_units(const WorkUnits& w, const PilotPhotonCount& p) {
    return w.path + w.collision * p.collisions_per_photon + w.stored * p.stored_per_photon;
}

namespace {

// The photon pass's counts into p (the map sizes are added as they are built).
void add_trace_counts(const PhotonTraceResult& traced, std::ostream* log, bool store_auto, PhotonPassStats& p) {
    const size_t stored = traced.photons.size();
    p.emitted = traced.paths;
    p.stored = stored;
    p.collisions = traced.collisions;
    p.storing_walks = traced.storing_walks;
    p.store_probability = traced.store_probability;
    if (log && store_auto)
        *log << "photons: store_probability = \"auto\": " << traced.store_probability << " after the first 4096 photons ("
             << traced.storing_walks << " walks stored " << stored << " volume photons in all)\n";
    p.truncated_paths = traced.truncated_paths;
    p.paths_per_second = traced.seconds > 0 ? double(traced.paths) / traced.seconds : 0.0;
    p.energy = traced.energy;
    if (log)
        *log << "trace: " << traced.paths << " photon paths, " << traced.collisions << " collisions, " << stored
             << " stored in " << traced.seconds << " s; energy imbalance " << traced.energy.relative_imbalance()
             << ", truncated paths " << traced.truncated_paths << "\n";
}

}  // namespace

PhotonMaps run_photon_pass(const Scene& scene, const PhotonMapSettings& ps, const PassContext& context,
                           bool surface, RunStats& stats, std::optional<LightAllocation>& cached) {
    // The report lines are written for a run's first pass; later passes add one "pass" line each.
    std::ostream* log = context.first_of_run ? context.log : nullptr;
    PhotonTraceSettings ts = trace_settings(scene, ps, context, surface, cached);
    // Stops before the real work when the pilot chunk projects a map that cannot fit; progress lines.
    ts.on_chunk = make_photon_pass_guard(double(memory_limit_bytes()), context.log);
    const bool importance = ps.allocation == PhotonAllocationRule::importance;
    const LightAllocation& allocation = *cached;
    PhotonTraceResult traced = trace_photons(scene, ts);
    // A cancelled task group (the Python module's Ctrl-C) stopped the trace: no kd-tree over its
    // partial photons (seconds for millions); the caller discards the run.
    if (tbb::is_current_task_group_canceling()) return PhotonMaps();
    stats.phase("trace", traced.seconds);
    const size_t stored = traced.photons.size();
    PhotonPassStats p;
    report_photon_lights(scene, importance ? "importance" : "power", allocation, traced, p, log);
    add_trace_counts(traced, log, ps.store_auto, p);
    // Warn before building a map (and the beams' BVH) larger than the budget (records + index, per
    // photon and per beam).
    p.projected_map_bytes = double(stored + traced.surface_photons.size()) * double(bytes_per_photon() + 4) +
                            double(traced.beams.size()) * peak_bytes_per_beam();
    p.memory_budget_bytes = ps.memory_budget_fraction * double(memory_limit_bytes());
    p.over_memory_budget = p.projected_map_bytes > p.memory_budget_bytes;
    if (p.over_memory_budget && log)
        *log << "warning: the photon map" << (traced.beams.empty() ? "" : " and its photon beams' BVH") << " will take about "
             << p.projected_map_bytes / 1e9 << " GB, over the budget of " << p.memory_budget_bytes / 1e9
             << " GB (photons.memory_budget_fraction of the memory this process may use)\n";

    PhotonMaps maps;
    if (ts.store_beams) {
        maps.beams = std::move(traced.beams);
        maps.beam_regions = std::move(traced.beam_regions);
        if (log)
            *log << "trace: " << maps.beams.size() << " photon beams (free flights in the media, "
                 << double(maps.beams.size()) / double(std::max<uint64_t>(traced.paths, 1)) << " per path)\n";
    }
    // A scene with glass shapes (photons carry regions): one more kd-tree per region, even where all
    // photons share one (a path in another region must find none there, not theirs).
    auto split = [](const std::vector<PhotonInput>& photons, const std::vector<RegionMask>& regions) {
        return regions.empty() ? RegionPhotonMaps() : RegionPhotonMaps(photons, regions);
    };
    if (surface) {
        maps.surface_regions = split(traced.surface_photons, traced.surface_photon_regions);
        if (log && !maps.surface_regions.empty())
            *log << "build: surface photon maps of " << maps.surface_regions.regions()
                 << " regions (glass interfaces, scene/dielectric_regions.h), " << maps.surface_regions.memory_bytes() / 1e6 << " MB\n";
    }
    maps.volume_regions = split(traced.photons, traced.photon_regions);
    if (log && !maps.volume_regions.empty())
        *log << "build: volume photon maps of " << maps.volume_regions.regions()
             << " regions (glass interfaces, scene/dielectric_regions.h), " << maps.volume_regions.memory_bytes() / 1e6 << " MB\n";
    if (surface) {
        const Timer surface_timer;
        const size_t n_surface = traced.surface_photons.size();
        maps.surface = PhotonMap(traced.surface_photons);
        std::vector<PhotonInput>().swap(traced.surface_photons);
        stats.phase("build_surface", surface_timer.seconds());
        p.surface_map = true;
        p.surface_hits = traced.surface_hits;
        p.surface_stored = n_surface;
        p.surface_map_bytes = maps.surface.memory_bytes();
        if (log)
            *log << "build: surface photon map, " << traced.surface_hits << " surface hits, " << n_surface
                 << " stored, kd-tree in " << surface_timer.seconds() << " s, " << maps.surface.memory_bytes() / 1e6
                 << " MB\n";
    }

    const Timer build_timer;
    maps.volume = PhotonMap(traced.photons);
    std::vector<PhotonInput>().swap(traced.photons);
    stats.phase("build", build_timer.seconds());
    p.bytes_per_photon = bytes_per_photon();
    p.map_bytes = maps.volume.memory_bytes();
    p.map_bytes_per_photon = stored ? double(p.map_bytes) / double(stored) : 0.0;
    PhotonMapStats::in(stats).add_photon_pass(p);
    if (log)
        *log << "build: kd-tree over " << stored << " photons in " << build_timer.seconds() << " s, "
             << p.map_bytes / 1e6 << " MB (" << p.map_bytes_per_photon << " bytes/photon)\n";
    return maps;
}

}  // namespace vpm
