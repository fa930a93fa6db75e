// photons.gather = "photon_beams" or "point_beam" under render.time_limit: the pilots that size
// their passes (render/photon_map/beam_pass_size.h), members of PhotonMapIntegrator.
#include <algorithm>
#include <sstream>

#include <tbb/parallel_for.h>

#include "core/error.h"
#include "core/progress.h"
#include "render/photon_map/gathers/photon_beams_gather.h"
#include "render/photon_map/gathers/point_beam_gather.h"
#include "render/photon_map/photon_map_integrator.h"
#include "render/photon_map/photon_map_stats.h"
#include "render/plan/pilot_pixels.h"

namespace vpm {

namespace {

// The larger pilot's photons (the smaller has a quarter): enough beams that most probe segments
// find k of them, few enough that sample-point widths (each beam's own k-nearest query, growing
// faster than the beams) stay a small part of a limit of seconds.
constexpr int64_t kBeamPilotPhotons = 4096;
// The camera probe: the centres of side x side image blocks, samples each.
constexpr int kBeamProbeSide = 16;
constexpr int kBeamProbeSamples = 2;
// Streams of the pilots: apart from every pass's (run.cpp spaces passes 2^20 apart from the run's offset).
constexpr uint64_t kBeamPilotStreams = uint64_t(1) << 62;

}  // namespace

BeamPilotCounts PhotonMapIntegrator::beam_pilot(const PassContext& context, int64_t photons, uint64_t salt) {
    PhotonMapSettings ps = settings_;
    ps.count = photons;
    PassContext pc = context;
    pc.log = nullptr;
    pc.progress = false;
    pc.first_of_run = false;
    pc.stream_offset = context.run_stream_offset + kBeamPilotStreams + salt;
    RunStats scratch;   // the pilot's phases and photon pass stay out of the run's record
    const bool surface = traces_surface_map();
    PhotonMaps maps = run_photon_pass(scene_, ps, pc, surface, scratch, photons_.allocation);
    BeamPilotCounts c;
    c.photons = double(photons);
    if (const auto& traced = PhotonMapStats::of(scratch).photons) {
        c.collisions = double(traced->collisions);
        c.surface_stored = double(traced->surface_stored);
    }
    SegmentGatherInputs inputs{scene_, ps, maps.volume, maps.beams, pass_.k, pass_.max_radius, pass_.beam_scale,
                               maps.volume_regions.empty() ? nullptr : &maps.volume_regions,
                               maps.beam_regions.empty() ? nullptr : &maps.beam_regions};
    std::unique_ptr<SegmentGather> gather = gather_entry(settings_.gather).build(inputs);
    const auto* beams = dynamic_cast<const PhotonBeamsGather*>(gather.get());
    const auto* discs = dynamic_cast<const PointBeamGather*>(gather.get());
    if (beams) {
        const PhotonBeamsGatherStats built = beams->stats();
        c.beams = double(built.beams);
        c.pieces = double(built.pieces);
        c.width_tests = double(built.widths_tested);
    } else {
        c.beams = double(discs->stats().photons);   // one radius query and one BVH item per disc
        c.pieces = c.beams;
    }

    PassMaps pm = pass_maps(pass_, settings_.gather, maps.volume, surface ? &maps.surface : nullptr, decision_.view(),
                            maps.volume_regions.empty() ? nullptr : &maps.volume_regions,
                            surface && !maps.surface_regions.empty() ? &maps.surface_regions : nullptr);
    pm.segment = gather->usable() ? gather.get() : nullptr;
    if (!gather->usable()) pm.gather = GatherMode::march;
    const CameraPath path(scene_, settings_, pm, both_strategies_);
    CounterSet counters;
    const Camera& camera = scene_.camera;
    constexpr int kPixels = kBeamProbeSide * kBeamProbeSide;
    const uint64_t seed = mix64(context.seed ^ 0x6265616d70696c6fULL);   // "beampilo"
    tbb::parallel_for(0, kPixels, [&](int j) {
        const auto [px, py] = block_centre(j, kBeamProbeSide, camera.width(), camera.height());
        for (int s = 0; s < kBeamProbeSamples; ++s) {
            Rng rng(seed, context.run_stream_offset * uint64_t(kPixels * kBeamProbeSamples) + uint64_t(j * kBeamProbeSamples + s) + salt);
            const double jx = rng.uniform(), jy = rng.uniform();
            path.trace(camera.generate_ray(px + jx, py + jy), 0, rng, counters.local());
        }
    });
    c.samples = double(kPixels * kBeamProbeSamples);
    c.camera = counted_operations(counters);
    if (beams) {
        const PhotonBeamsGatherStats probed = beams->stats();
        c.beam_queries = double(probed.queries);
        c.beam_tests = double(probed.tested);
    } else {
        const PointBeamGatherStats probed = discs->stats();
        c.beam_queries = double(probed.queries);
        c.beam_tests = double(probed.crossed);
    }
    return c;
}

void PhotonMapIntegrator::plan_beam_pass(const PassContext& context, RunStats& stats) {
    const Timer timer;
    BeamPassInputs in;
    const int64_t large = std::min<int64_t>(settings_.count, kBeamPilotPhotons);
    const int64_t small = std::max<int64_t>(1, large / 4);
    try {
        in.small = beam_pilot(context, small, 1);
        in.large = beam_pilot(context, large, 2);
    } catch (const Error& e) {
        // Sample-point widths refuse a pilot map whose beams do not cross: no sizing from it.
        choice_.beam_pass = BeamPassSize{settings_.count, context.configured_spp};
        stats.warn(std::string(gather_entry(settings_.gather).name) + " under render.time_limit: the pilot maps of " + std::to_string(small) + " and " +
                       std::to_string(large) + " photons could not be built (" + e.what() +
                       "), so the passes keep photons.count and render.spp and may overrun the limit",
                   context.log);
        photons_.one_off_seconds += timer.seconds();
        return;
    }
    in.units = work_units(scene_, int(pass_.k));
    if (settings_.gather == GatherMode::point_beam) {
        // Each disc's radius: a k-nearest query at beam_k, priced over the largest map considered.
        const double stored = std::max(1.0, in.large.beams / std::max(1.0, in.large.photons) * double(settings_.count));
        in.beam_units = point_beam_work_units(query_price(work_units(scene_, settings_.beam_k), stored));
        in.least_test_growth = kLeastDiscTestGrowth;
    } else {
        in.beam_units = beam_work_units();
        in.balance_camera = true;
        in.least_spp = kBeamLeastSpp;
        if (settings_.beam_widths == BeamWidths::density) in.least_width_growth = kLeastDensityWidthGrowth;
    }
    in.pixels = double(scene_.camera.width()) * double(scene_.camera.height());
    in.count = settings_.count;
    in.spp = context.configured_spp;
    in.size_photons = settings_.size_beam_photons;
    in.size_samples = settings_.size_beam_samples;
    in.budget = settings_.time_limit * kWorkUnitsPerSecond;
    choice_.beam_pass = size_beam_pass(in);
    photons_.ledger.probe += uint64_t(small + large);
    const double seconds = timer.seconds();
    photons_.one_off_seconds += seconds;
    stats.phase("beam_pass_pilot", seconds);
    const BeamPassSize& b = *choice_.beam_pass;
    const bool discs = settings_.gather == GatherMode::point_beam;
    std::ostringstream s;
    s.precision(3);
    s << gather_entry(settings_.gather).name << ": render.time_limit = " << settings_.time_limit << " s sizes the pass from counted work (pilots of "
      << small << " and " << large << " photons, " << seconds << " s): " << b.count << " photons"
      << (settings_.size_beam_photons ? "" : " (photons.count)") << " and " << b.spp << " spp"
      << (settings_.size_beam_samples ? "" : " (render.spp / render.passes)") << " per pass, projected "
      << b.pass_units / kWorkUnitsPerSecond << " s of one core (photon pass, " << (discs ? "radii and BVH " : "BVH and widths ")
      << b.map_units / kWorkUnitsPerSecond << " s) for a pass budget of " << b.pass_budget / kWorkUnitsPerSecond << " s; "
      << (discs ? "discs crossed" : "crossing tests") << " per query grow as N^" << b.test_growth;
    if (!discs) s << ", width tests per beam as N^" << b.width_growth;
    s << "\n";
    if (context.log) *context.log << s.str();
    if (!b.fits) {
        std::ostringstream w;
        w.precision(3);
        w << "render.time_limit = " << settings_.time_limit << " s: one " << gather_entry(settings_.gather).name << " pass of " << b.count << " photons at " << b.spp
          << " spp counts " << b.pass_units / kWorkUnitsPerSecond << " s of one core, more than its budget of "
          << b.pass_budget / kWorkUnitsPerSecond << " s, and a pass is not cut short";
        if (!settings_.size_beam_photons || !settings_.size_beam_samples)
            w << " (" << (settings_.size_beam_photons ? "" : "photons.count ") << (settings_.size_beam_samples ? "" : "render.spp ")
              << "pinned: --unset lets the limit size them)";
        stats.warn(w.str(), context.log);
    }
}

}  // namespace vpm
