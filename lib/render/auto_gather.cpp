// photons.gather = "auto": the map-noise pilot and the pass plan (render/pass_plan.h), run once on
// the first pass of a run. A member of PhotonMapIntegrator kept apart from its camera paths.
#include <algorithm>
#include <ostream>

#include "core/progress.h"
#include "core/rng.h"
#include "render/map_noise_pilot.h"
#include "render/photon_map_integrator.h"
#include "render/work_units.h"

namespace vpm {

int PhotonMapIntegrator::samples_per_pass(int configured) const {
    return plan_ && settings_.size_samples ? plan_->spp : configured;
}

void PhotonMapIntegrator::plan_auto(const PassContext& context, RunStats& stats) {
    const Timer timer;
    const WorkUnits w = work_units(scene_, int(k_));
    PlanInputs in;
    in.pixels = double(scene_.camera.width()) * double(scene_.camera.height());
    in.count = settings_.count;
    // The configured pass: the plan's sizes start from it, and a pass over budget / kPlanMinPasses
    // may still be as large as it (when unsized the plan only picks the gather at these samples).
    in.spp = std::max(1, context.configured_spp);
    in.size_photons = owns_maps_ && settings_.size_photons;
    in.size_samples = settings_.size_samples;
    in.budget = settings_.time_limit * kWorkUnitsPerSecond;
    // The pilot's map is pass 0's, so that every range of passes rendered apart (render.first_pass,
    // vpm merge) makes the same plan: a run starting later traces it apart, with pass 0's streams.
    PhotonMaps pilot_maps;
    const PhotonMap* map = map_;
    std::optional<PhotonPassStats> counts = stats.photons;
    if (owns_maps_ && context.pass != 0) {
        PassContext c = context;
        c.stream_offset = context.run_stream_offset;
        c.pass = 0;
        c.first_of_run = false;
        c.progress = false;
        c.log = nullptr;
        RunStats pilot_stats;
        pilot_maps = run_photon_pass(scene_, settings_, c, false, pilot_stats, allocation_);
        map = &pilot_maps.volume;
        counts = pilot_stats.photons;
    }
    if (counts && counts->emitted > 0)
        in.photon_cost = (w.collision * double(counts->collisions) + w.path * double(counts->emitted) +
                          w.stored * double(counts->stored)) / double(counts->emitted);
    const std::vector<std::string> names = {"collision", "march"};
    const Gather gathers[] = {Gather::collision, Gather::march};
    std::vector<GatherMeasurement> measured;
    const PhotonMap* run_map = map_;
    if (map->size() > 0) {
        MapNoisePilotHooks hooks;
        hooks.use = [&](int c, const PhotonMap* m) {
            gather_ = gathers[c];
            map_ = m;
        };
        hooks.trace = [&](const Ray& ray, Rng& rng) { return trace(ray, 0, rng); };
        hooks.counts = [&] { return counted_operations(); };
        hooks.work = [&](const CountedOperations& c) { return w.query * c.queries + w.ray * c.rays + w.lookup * c.lookups; };
        with_fresh_counters([&] {
            measured = measure_gathers(scene_.camera, *map, names, hooks,
                                       mix64(context.seed ^ 0x6d61706e6f697365ULL), context.run_stream_offset);
        });
        map_ = run_map;
    } else {
        for (const auto& n : names) measured.push_back(GatherMeasurement{n, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, {}});
    }
    in.candidates = measured;
    PassPlan plan = plan_passes(in);
    if (!in.size_samples) plan.spp = 0;   // not the plan's: samples_per_pass keeps the configured value
    gather_ = gathers[plan.chosen];
    plan_ = plan;
    AutoGatherStats a;
    a.candidates = measured;
    a.photon_cost = in.photon_cost;
    a.chosen = names[size_t(plan.chosen)];
    a.count = in.size_photons ? plan.count : settings_.count;
    a.spp = plan.spp;
    a.beta = plan.beta;
    a.beta_measured = plan.beta_measured;
    a.size_photons = in.size_photons;
    a.size_samples = in.size_samples;
    auto_stats_ = a;
    stats.phase("pilot", timer.seconds());
    if (context.log) {
        std::ostream& log = *context.log;
        log << "gather: auto chose \"" << a.chosen << "\" (pilot: " << kPilotSide * kPilotSide << " pixels x "
            << kPilotSamples << " samples with the map and its halves";
        if (map->size() == 0) log << "; the volume map is empty, nothing to measure";
        for (const auto& m : measured)
            log << "; " << m.name << ": per-sample variance " << m.v_camera << ", map variance at N/2 " << m.v_map_half
                << ", squared bias " << m.bias2 << ", mean " << m.mean << " +- " << m.mean_se
                << (m.max_weight > kPlanMaxMarchWeight ? ", not trusted: march weights up to " + std::to_string(m.max_weight) : std::string())
                << ", work " << m.sample_cost << " per sample";
        log << "; work " << in.photon_cost << " per photon)\n";
        if (in.size_photons || in.size_samples)
            log << "passes: " << a.count << " photons per pass after the first (" << (in.size_photons ? "sized" : "photons.count")
                << "), " << (in.size_samples ? std::to_string(plan.spp) : std::string("render.spp")) << " samples per pass ("
                << (in.size_samples ? "sized" : "given") << "), the map's variance taken as N^-" << plan.beta
                << (plan.beta_measured ? " (measured)" : " (assumed)") << "\n";
    }
}

}  // namespace vpm
