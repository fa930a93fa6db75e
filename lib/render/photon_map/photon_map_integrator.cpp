#include "render/photon_map/photon_map_integrator.h"

#include <algorithm>
#include <array>
#include <map>
#include <optional>
#include <ostream>
#include <sstream>

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "core/henyey_greenstein.h"
#include "core/progress.h"
#include "core/sampling.h"
#include "photon/estimate/ball_extinction.h"
#include "photon/estimate/bounded_radius.h"
#include "render/photon_map/beam_gather.h"
#include "render/photon_map/photon_beam_gather.h"
#include "render/plan/pass_plan.h"
#include "render/plan/work_units.h"
#include "transport/seen_through.h"
#include "transport/segment_direct_light.h"
#include "transport/single_scattering.h"
#include "transport/specular_step.h"
#include "scene/media/homogeneous_medium.h"
#include "photon/estimate/group_estimate.h"
#include "photon/estimate/linear_estimate.h"
#include "config/params.h"
#include "scene/dielectric_regions.h"
#include "transport/direct_light.h"
#include "transport/equiangular.h"
#include "transport/march_points.h"
#include "transport/mis.h"
#include "transport/walk_steps.h"

namespace vpm {

namespace {

double total_sigma_t(const Scene& scene, const Vec3& x) {
    double sigma_t = 0.0;   // overlapping media: photons of all of them are in the map
    for (const auto& m : scene.media) sigma_t += m->sigma_t(x);
    return sigma_t;
}


}  // namespace

// "threshold", and "auto" or "pilot" before its pilot has run (no prepare()): the per-segment threshold.
PhotonMapIntegrator::Gather initial_gather(GatherMode mode) {
    switch (mode) {
        case GatherMode::collision: return PhotonMapIntegrator::Gather::collision;
        case GatherMode::march: return PhotonMapIntegrator::Gather::march;
        case GatherMode::beam: return PhotonMapIntegrator::Gather::beam;
        case GatherMode::photon_beams: return PhotonMapIntegrator::Gather::photon_beams;
        case GatherMode::automatic:
        case GatherMode::pilot:
        case GatherMode::threshold: break;
    }
    return PhotonMapIntegrator::Gather::threshold;
}

struct PhotonMapIntegrator::ThreadState {
    explicit ThreadState(const Scene& scene) : ball(scene.media) {}
    explicit ThreadState(const BallExtinction& shared) : ball(shared) {}   // the same box masses and mass lattices
    BallExtinction ball;   // mean sigma_t over kNN balls (photons.extinction = "ball")
    struct Local {
        GatherBuffers buffers;
        EstimatorStats stats, surface_stats;
        uint64_t continued = 0;   // camera paths continued past a collision (bounded radius)
        uint64_t linear_fallbacks = 0;   // linear estimates that fell back to the ball's (photon/estimate/linear_estimate.h)
        uint64_t march_wide = 0;  // march queries whose kNN ball exceeds max_radius_mfp mean free paths
        uint64_t rays = 0;        // tracked segments: free flights, shadow rays, march transmittances (pilot cost)
        uint64_t lookups = 0;     // sigma_t lookups of the ball quadrature (pilot cost)
        double march_weight_max = 0.0, march_weight_sum = 0.0;   // relative march point weights
        uint64_t march_points = 0;
        uint64_t map_used = 0;    // estimates taken from a map, not continued past (pilot: render/plan/no_map_candidate.h)
        uint64_t decisions = 0;   // queries of the bound's decision map
        std::vector<Rgb> linear_weights;   // photons.extinction = "linear"
        OpticalDepthProfile profile;       // transport/seen_through.h (no path is traced while it is in use)
        RegionMask region = 0;             // the region of the camera path being traced (trace())
    };
    mutable tbb::enumerable_thread_specific<Local> local;
};

PhotonMapIntegrator::PhotonMapIntegrator(const Scene& scene, const PhotonMapSettings& settings)
    : scene_(scene), settings_(settings), owns_maps_(true), map_(&owned_.volume), surface_map_(nullptr),
      max_radius_(settings.search_radius()), k_(size_t(settings.k)), volume_estimator_(settings.estimator),
      surface_estimator_(settings.estimator), threads_(std::make_unique<ThreadState>(scene)),
      continuation_(scene, settings.walk) {
    gather_ = initial_gather(settings.gather);
    both_strategies_ = settings.walk.mis && bounces_find_lights(scene);
}

PhotonMapIntegrator::PhotonMapIntegrator(const Scene& scene, const PhotonMapSettings& settings,
                                         const PhotonMap& volume_map, const PhotonMap* surface_map)
    : scene_(scene), settings_(settings), owns_maps_(false), map_(&volume_map), surface_map_(surface_map),
      max_radius_(settings.search_radius()), k_(size_t(settings.k)), volume_estimator_(settings.estimator),
      surface_estimator_(settings.estimator), threads_(std::make_unique<ThreadState>(scene)),
      continuation_(scene, settings.walk) {
    gather_ = initial_gather(settings.gather);
    both_strategies_ = settings.walk.mis && bounces_find_lights(scene);
    schedule_pass(0);
    if (gather_ == Gather::beam) build_beam(nullptr, nullptr);
}

PhotonMapIntegrator::~PhotonMapIntegrator() = default;

void PhotonMapIntegrator::schedule_pass(int pass) {
    const PassRadii r = settings_.radii_for_pass(pass, scene_.has_media(), surface_map_ != nullptr || traces_surface_map());
    k_ = size_t(r.k);
    volume_estimator_ = settings_.estimator.with_radius_scale(r.volume_scale);
    surface_estimator_ = settings_.estimator.with_radius_scale(r.surface_scale);
    beam_scale_ = r.beam_scale;
}

void PhotonMapIntegrator::prepare(const PassContext& context, RunStats& stats) {
    schedule_pass(context.pass);
    if (radii_log_.radii.size() < RunStats::kPassRecords) {
        radii_log_.pass.push_back(context.pass);
        radii_log_.radii.push_back(settings_.radii_for_pass(context.pass, scene_.has_media(), surface_map_ != nullptr || traces_surface_map()));
    }
    radii_log_.last_pass = context.pass;
    // A run starting at a later pass plans on pass 0's map first: a plan without the map then saves this pass's.
    if (owns_maps_ && settings_.plans() && !plan_ && context.pass != 0) plan_auto(context, stats);
    if (!owns_maps_) {
        if (settings_.gather == GatherMode::pilot) choose_gather(context);
        if (settings_.plans() && !plan_) plan_auto(context, stats);
        return;
    }
    std::ostream* log = context.first_of_run ? context.log : nullptr;
    const bool surface = traces_surface_map();
    if (no_map_) {   // render/plan/no_map_candidate.h: the plan found the map not worth its pass
        owned_ = PhotonMaps();
        surface_map_ = nullptr;
    } else if (scene_.has_media() || surface) {
        // Pass 0 of an auto plan is first traced at photons.count: the pilot's map, which the plan is made on.
        trace_maps(context, plan_ ? plan_->count : first_map_photons(context, stats), surface, stats);
        if (!decision_map_ && wants_decision_map()) trace_decision_map(context, stats);
        // k above the stored count: say so once per run (the maps are then not queried).
        const bool volume_short = scene_.has_media() && settings_.gather != GatherMode::photon_beams && volume_map_starved();
        const bool surface_short = surface_map_ && surface_map_->size() < k_;
        if ((volume_short || surface_short) && !warned_k_ && context.log) {
            warned_k_ = true;
            *context.log << "warning: photons.k = " << k_ << " exceeds the " << (volume_short ? map_->size() : surface_map_->size())
                         << (volume_short ? " volume" : " surface") << " photons stored in pass " << context.pass
                         << ": no estimate can use k photons, so camera paths are path traced past every "
                         << (volume_short ? "medium collision" : "surface hit") << " instead (lower photons.k or raise photons.count)\n";
        }
        if (settings_.gather == GatherMode::beam) build_beam(log, &stats);
        if (settings_.gather == GatherMode::photon_beams) build_photon_beams(log, &stats);
    } else if (log) {
        *log << "photons: no media and no surface map, so no photon pass\n";
    }
    if (!scene_.has_media() && log) *log << "photons: no media, so the volume photon map is empty\n";
    if (settings_.gather == GatherMode::pilot) choose_gather(context);
    if (settings_.plans() && !plan_) {
        plan_auto(context, stats);
        // Rendered with the pilot's small map, pass 0 would keep that map's bias and noise in the
        // image (all of it where the time limit allows one pass): it is traced again at the plan's
        // size, as every later pass is, and as a run starting at a later pass renders it.
        if (!no_map_ && plan_->count > first_map_photons_ && (scene_.has_media() || surface)) {
            if (log)
                *log << "photons: pass 0 traced again with the plan's " << plan_->count << " photons (the pilot's "
                     << first_map_photons_ << " only chose the plan)\n";
            one_off_seconds_ += last_trace_seconds_;   // the pilot's map
            ledger_.pass_maps -= uint64_t(first_map_photons_);   // it served the pilot alone
            ledger_.pilot_only += uint64_t(first_map_photons_);
            ledger_.passes_traced -= 1;
            trace_maps(context, plan_->count, surface, stats);
        }
    }
    if (scene_.uses_embree() && !surface && log)
        *log << "photons: final_gather = true, so no surface photon map (paths continue through surfaces)\n";
}

int64_t PhotonMapIntegrator::first_map_photons(const PassContext& context, RunStats& stats) {
    if (first_map_photons_ > 0) return first_map_photons_;
    first_map_photons_ = settings_.count;
    if (owns_maps_ && settings_.size_photons && scene_.has_media()) {
        const Timer probe_timer;
        const PilotPhotonCount p = pilot_photon_count(scene_, settings_, context, traces_surface_map(), allocation_);
        one_off_seconds_ += probe_timer.seconds();
        first_map_photons_ = p.count;
        ledger_.probe += uint64_t(p.probe_photons);
        if (context.log && context.first_of_run && p.count < settings_.count)
            *context.log << "photons: the pilot's map of " << p.count << " photons, not photons.count = " << settings_.count
                         << ": a probe of " << p.probe_photons << " stored " << p.stored_per_photon << " per photon, and "
                         << kPilotStoredPhotons << " stored are what the pilot needs (render/photon_map/photon_pass.h)\n";
    }
    if (owns_maps_ && !settings_.size_photons && settings_.time_limit > 0.0 && scene_.has_media())
        check_pinned_count_fits(context, stats);
    return first_map_photons_;
}

// photons.count pinned under render.time_limit: the pass is traced at that count whatever the
// limit, so a probe's counted work (render/plan/work_units.h: deterministic, no clock) says before
// the trace whether its photon pass alone fits, and a warning (log and sidecar) names the count that would.
void PhotonMapIntegrator::check_pinned_count_fits(const PassContext& context, RunStats& stats) {
    const Timer probe_timer;
    const PilotPhotonCount p = pilot_photon_count(scene_, settings_, context, traces_surface_map(), allocation_);
    one_off_seconds_ += probe_timer.seconds();
    ledger_.probe += uint64_t(p.probe_photons);
    const WorkUnits w = work_units(scene_, k_);
    double per_photon = w.path + w.collision * p.collisions_per_photon + w.stored * p.stored_per_photon;
    // The point-beam gather then finds every stored photon's radius: a kNN query each.
    if (settings_.gather == GatherMode::beam)
        per_photon += p.stored_per_photon * query_price(w, std::max(1.0, p.stored_per_photon * double(settings_.count)));
    const double budget = settings_.time_limit * kWorkUnitsPerSecond, work = per_photon * double(settings_.count);
    if (!(work > budget)) return;
    std::ostringstream s;
    s.precision(3);
    s << "render.time_limit = " << settings_.time_limit << " s: photons.count = " << settings_.count
      << (settings_.count_given ? " is set" : " (its default)") << ", and its photon pass alone counts " << work / kWorkUnitsPerSecond << " s of one core (a probe of "
      << p.probe_photons << " photons: " << p.collisions_per_photon << " collisions and " << p.stored_per_photon
      << " stored per photon), so the first pass overruns the limit; ";
    if (const double fit = std::floor(budget / per_photon); fit >= 1.0) s << "about " << fit << " photons fit";
    else s << "not one photon fits";
    // A count the plan could have sized was set by the user; for the other gathers it may be the default.
    if (settings_.plan_sizes_passes()) s << ", or leave photons.count unset for the plan to size it";
    else s << " (the plan sizes photons only for the \"collision\" and \"march\" gathers: set photons.count to fit)";
    stats.warn(s.str(), context.log);
}

void PhotonMapIntegrator::trace_maps(const PassContext& context, int64_t count, bool surface, RunStats& stats) {
    retire_beam();           // its BVH points into the last pass's map
    retire_photon_beams();
    owned_ = PhotonMaps();   // one map in memory at a time: free the last pass's first
    PhotonMapSettings pass_settings = settings_;
    pass_settings.count = count;
    const Timer timer;
    owned_ = run_photon_pass(scene_, pass_settings, context, surface, stats, allocation_);
    last_trace_seconds_ = timer.seconds();
    ledger_.pass_maps += uint64_t(count);
    ledger_.passes_traced += 1;
    surface_map_ = surface ? &owned_.surface : nullptr;
    use_regions(owned_.volume_regions.empty() ? nullptr : &owned_.volume_regions,
                owned_.surface_regions.empty() ? nullptr : &owned_.surface_regions);
    set_map_emitted(double(count));
}

bool PhotonMapIntegrator::traces_surface_map() const {
    return scene_.uses_embree() && !settings_.final_gather;
}

bool PhotonMapIntegrator::wants_decision_map() const {
    return scene_.has_media() && settings_.max_radius_mfp > 0.0 && settings_.gather != GatherMode::beam &&
           settings_.gather != GatherMode::photon_beams;
}

void PhotonMapIntegrator::trace_decision_map(const PassContext& context, RunStats& stats) {
    // Its own seed, and the run's streams rather than the pass's: independent of every pass's map, and
    // the same map on every machine rendering passes of the run (vpm merge).
    PassContext c = context;
    c.seed = mix64(context.seed ^ 0x646563697369ULL);
    c.stream_offset = context.run_stream_offset;
    c.first_of_run = false;
    c.log = nullptr;
    RunStats traced;   // its counts are not the run's photon passes'
    PhotonMapSettings decision_settings = settings_;
    // An eighth of photons.count, also where the auto plan's pilot map is smaller (render/photon_map/photon_pass.h):
    // the passes that keep the map have photons.count or more, and the decision's ball and count were
    // measured at that ratio (docs/studies/heldout_scenes.md section 31).
    decision_settings.count = std::max<int64_t>(1, settings_.count / kDecisionMapShare);
    // The run's photons per light (traced after its first map, which set them).
    decision_owned_ = std::move(run_photon_pass(scene_, decision_settings, c, false, traced, allocation_).volume);
    decision_map_ = &decision_owned_;
    decision_cells_ = PhotonCellCounts(decision_owned_);
    decision_emitted_ = double(decision_settings.count);
    ledger_.decision_map += uint64_t(decision_settings.count);
    set_map_emitted(map_emitted_);
    double seconds = 0.0;
    for (const PhaseStats& phase : traced.phases) seconds += phase.seconds;
    stats.phase("decision_map", seconds);
    one_off_seconds_ += seconds;
    stats.decision_map_photons = decision_owned_.size();
    if (context.log && context.first_of_run)
        *context.log << "photons: decision map of " << decision_settings.count << " photons (" << decision_owned_.size()
                     << " stored) in " << seconds << " s: photons.max_radius_mfp's switch is decided on it, apart from "
                     << "the maps it selects (photon/estimate/bounded_radius.h)\n";
}

void PhotonMapIntegrator::set_map_emitted(double emitted) {
    map_emitted_ = emitted;
    if (decision_emitted_ > 0.0) decision_ratio_ = emitted / decision_emitted_;
}

void PhotonMapIntegrator::decide_bound_on(const PhotonMap* map, double emitted_ratio) {
    decision_map_ = map;
    decision_cells_ = map ? PhotonCellCounts(*map) : PhotonCellCounts();
    decision_emitted_ = 0.0;   // not owned: the ratio is given
    decision_ratio_ = emitted_ratio;
}

PhotonMapIntegrator::DecisionBall PhotonMapIntegrator::decision_ball(double radius) const {
    // The map's k photons within R, in the decision map's density: k N_d / N photons expected within
    // R, at least kDecisionMinK of them (a smaller count decides by its noise), within the ball that
    // holds that many on average.
    DecisionBall d;
    d.k = std::min(k_, std::max(kDecisionMinK, size_t(std::lround(double(k_) / decision_ratio_))));
    d.radius = radius * std::cbrt(double(d.k) / double(k_) * decision_ratio_);
    return d;
}

uint64_t PhotonMapIntegrator::decision_queries() const {
    uint64_t total = 0;
    for (const auto& l : threads_->local) total += l.decisions;
    return total;
}

std::string PhotonMapIntegrator::gather_used() const {
    if (no_map_) return "none";
    switch (gather_) {
        case Gather::collision: return "collision";
        case Gather::march: return "march";
        case Gather::threshold: return "threshold";
        case Gather::beam: return "beam";
    }
    return "collision";
}

uint64_t PhotonMapIntegrator::map_estimates() const {
    uint64_t total = 0;
    for (const auto& l : threads_->local) total += l.map_used;
    return total;
}

void PhotonMapIntegrator::collect(RunStats& stats, std::ostream* log) const {
    stats.integrator_used = integrator_used();
    stats.gather_used = gather_used();
    stats.map_estimates = map_estimates();
    if (owns_maps_) {
        PhotonLedger l = ledger_;
        l.estimates = *stats.map_estimates;
        l.decision_queries = decision_map_ ? decision_queries() : 0;
        stats.photon_ledger = l;
        if (log)
            *log << "photons traced per phase: " << l.pass_maps << " in " << l.passes_traced << " passes' maps ("
                 << l.estimates << " estimates taken from them), " << l.pilot_only << " for the pilot alone, " << l.probe
                 << " in the probe that sized the pilot's map, " << l.decision_map << " in the decision map ("
                 << l.decision_queries << " radius decisions queried it)\n";
    }
    stats.volume_estimates = this->stats();
    if (!radii_log_.radii.empty()) {
        PassRadiiStats r = radii_log_;
        r.schedule = settings_.schedule == KSchedule::fixed ? "fixed" : settings_.schedule == KSchedule::shrink ? "shrink" : "progressive";
        r.alpha_points = settings_.alpha_for(3);
        r.alpha_surfaces = settings_.alpha_for(2);
        r.last = settings_.radii_for_pass(r.last_pass, scene_.has_media(), surface_map_ != nullptr || traces_surface_map());
        stats.pass_radii = r;
    }
    if (pilot_) stats.gather_pilot = pilot_;
    if (auto_stats_) stats.auto_gather = auto_stats_;
    stats.continued_paths = continued_paths();
    if (settings_.extinction == ExtinctionNormalisation::linear) {
        uint64_t fallbacks = 0;
        for (const auto& l : threads_->local) fallbacks += l.linear_fallbacks;
        stats.linear_fallbacks = fallbacks;
        if (fallbacks && log)
            *log << "linear: " << fallbacks << " of " << stats.volume_estimates->queries << " estimates fell back to the "
                 << "ball normalisation (their linear-corrected sum was negative; photon/estimate/linear_estimate.h)\n";
    }
    if (decision_map_) stats.decision_queries = decision_queries();
    if (log)
        *log << "estimates: " << stats.volume_estimates->to_string() << "; camera paths continued past a collision "
             << "(fewer than k photons within photons.max_radius_mfp, or in the map): " << *stats.continued_paths
             << (decision_map_ ? "; decision map queries: " + std::to_string(*stats.decision_queries) : std::string()) << "\n";
    if (settings_.gather != GatherMode::collision) {
        uint64_t wide = 0, points = 0;
        double wmax = 0.0, wsum = 0.0;
        for (const auto& l : threads_->local) {
            wide += l.march_wide;
            points += l.march_points;
            wmax = std::max(wmax, l.march_weight_max);
            wsum += l.march_weight_sum;
        }
        stats.march_wide_queries = wide;
        if (points > 0) {
            stats.march_weight_max = wmax;
            stats.march_weight_mean = wsum / double(points);
        }
        if (wide > 0 && log)
            *log << "march: " << wide << " march points took NEE and a continued path instead of an estimate (a kNN "
                 << "ball wider than photons.max_radius_mfp = " << settings_.max_radius_mfp
                 << " mean free paths, or fewer than k = " << k_ << " photons in the map); "
                 << stats.volume_estimates->queries << " map queries in all\n";
    }
    if (beam_) {
        stats.beam = beam_->stats();
        stats.beam->radii_seconds += beam_before_.radii_seconds;
        stats.beam->bvh_seconds += beam_before_.bvh_seconds;
        stats.beam->queries += beam_before_.queries;
        stats.beam->crossed += beam_before_.crossed;
        stats.beam->tracking_lookups += beam_before_.tracking_lookups;
        if (log)
            *log << "beam: " << stats.beam->queries << " segment queries crossed " << stats.beam->crossed << " photon discs ("
                 << (stats.beam->queries ? double(stats.beam->crossed) / double(stats.beam->queries) : 0.0) << " per query)\n";
    }
    if (photon_beams_) {
        PhotonBeamGatherStats b = photon_beams_->stats();
        b.widths_seconds += photon_beams_before_.widths_seconds;
        b.bvh_seconds += photon_beams_before_.bvh_seconds;
        b.queries += photon_beams_before_.queries;
        b.crossed += photon_beams_before_.crossed;
        b.tested += photon_beams_before_.tested;
        b.starved += photon_beams_before_.starved;
        b.tracking_lookups += photon_beams_before_.tracking_lookups;
        stats.photon_beams = b;
        if (log)
            *log << "photon_beams: " << b.queries << " segment queries weighed " << b.crossed << " beams ("
                 << (b.queries ? double(b.crossed) / double(b.queries) : 0.0) << " per query, "
                 << (b.queries ? double(b.tested) / double(b.queries) : 0.0) << " crossing tests per query); "
                 << b.starved << " found fewer than k beams (estimate 0)\n";
    }
    const EstimatorStats ss = surface_stats();
    if (ss.queries) {
        stats.surface_estimates = ss;
        if (log) *log << "surface estimates: " << ss.to_string() << "\n";
    }
}

EstimatorStats PhotonMapIntegrator::stats() const {
    EstimatorStats total;
    for (const auto& l : threads_->local) total.merge(l.stats);
    return total;
}

uint64_t PhotonMapIntegrator::continued_paths() const {
    uint64_t total = 0;
    for (const auto& l : threads_->local) total += l.continued;
    return total;
}

EstimatorStats PhotonMapIntegrator::surface_stats() const {
    EstimatorStats total;
    for (const auto& l : threads_->local) total.merge(l.surface_stats);
    return total;
}

Rgb PhotonMapIntegrator::radiance(const Ray& camera_ray, Rng& rng) const {
    if (no_map_) return continuation_.radiance(camera_ray, rng);
    return trace(camera_ray, 0, rng, EmissionWeighting::camera());
}

Rgb PhotonMapIntegrator::single_scattering(const Vec3& x, const Vec3& dir, double g, bool goes_on, Rng& rng,
                                           const SegmentPoint* at) const {
    if (goes_on) return direct_light_in_medium(scene_, x, dir, g, rng, settings_.walk.mis, at);
    if (!both_strategies_) return direct_light_in_medium(scene_, x, dir, g, rng, false, at);
    uint64_t rays = 0;
    const Rgb l = single_scattering_both_strategies(scene_, x, dir, g, rng, rays, at);
    threads_->local.local().rays += rays - 1;   // the caller counts one
    return l;
}

void PhotonMapIntegrator::use_regions(const RegionPhotonMaps* volume, const RegionPhotonMaps* surface) {
    volume_regions_ = volume;
    surface_regions_ = surface;
}

const PhotonMap& PhotonMapIntegrator::volume_map_here() const {
    return volume_regions_ ? volume_regions_->at(threads_->local.local().region) : *map_;
}

const PhotonMap* PhotonMapIntegrator::surface_map_here() const {
    if (!surface_map_) return nullptr;
    return surface_regions_ ? &surface_regions_->at(threads_->local.local().region) : surface_map_;
}

double PhotonMapIntegrator::region_share(const Vec3& x, double radius) const {
    if (!volume_regions_) return 1.0;
    return region_ball_fraction(scene_.surfaces.get(), x, radius, threads_->local.local().region);
}

Rgb PhotonMapIntegrator::trace(const Ray& first_ray, int first_depth, Rng& rng, const EmissionWeighting& first_emission) const {
    const int max_depth = settings_.walk.max_depth;
    // The path's region (scene/dielectric_regions.h), restored on return: a path continued from a
    // march point is traced inside the outer path's segment.
    RegionMask& region = threads_->local.local().region;
    struct RegionScope {
        RegionMask& region;
        const RegionMask outer;
        ~RegionScope() { region = outer; }
    } scope{region, region};
    if (volume_regions_ || surface_regions_) region = region_at(scene_.surfaces.get(), first_ray.origin);
    Ray ray = first_ray;
    Rgb throughput = Rgb::Ones();
    Rgb radiance = Rgb::Zero();
    // transport/mis.h. A path started deeper (first_depth > 0) continues from a march point: the
    // emission it meets counts as that point's NEE was weighted (transport/single_scattering.h).
    EmissionWeighting emission = first_emission;
    for (int depth = first_depth;; ++depth) {
        const PathVertex v = next_vertex(scene_, ray, rng);
        ++threads_->local.local().rays;
        const MediumEvent& event = v.medium;
        const SurfaceHit& hit = v.hit;
        const double t_end = v.on_surface ? hit.t : kInfinity;
        // A path continued from a march point (first_depth > 0) gathers at its collisions: marching
        // again would branch at every point, a tree that grows without bound where every ball is
        // wide (the stress matrix's furnace and pathological cells hung once "auto" chose the march).
        const bool march = first_depth == 0 && marches(ray, t_end);
        const bool beam = gather_ == Gather::beam || gather_ == Gather::photon_beams;
        // The collision gather's segments with direct = "nee", where every collision takes NEE: point
        // and spot lights are also sampled equiangularly along it (transport/equiangular.h). The march's
        // and the beam's segments do the same in march_in_scattering and segment_direct_light.
        std::optional<EquiangularSegment> segment;
        if (settings_.walk.equiangular && settings_.direct == DirectLighting::nee && !march && !beam &&
            !(max_depth >= 0 && depth + 1 > max_depth) && scene_.has_media()) {
            segment.emplace(scene_, ray, t_end);
            if (segment->empty())
                segment.reset();
            else
                radiance += throughput * segment->in_scattering(rng, threads_->local.local().rays,
                                                                [](size_t, double s, double, double tau) {
                                                                    return free_flight_density(s, tau);
                                                                });
        }
        if ((march || beam) && (!v.on_surface || hit.emitter)) {
            // The segment's in-scattering is gathered apart, so the sky or area light behind it is
            // weighed by the exact transmittance, not found by the free flight's trial
            // (transport/seen_through.h). The light is black: the path ends here either way.
            auto& local = threads_->local.local();
            const bool gathers = !(max_depth >= 0 && depth + 1 > max_depth);
            if (march && gathers) {
                // The march's profiles give the segment's optical depth: one walk, not two.
                double tau = 0.0;
                const Rgb in = march_in_scattering(ray, t_end, depth, rng, &tau);
                radiance += throughput * seen_through_depth(scene_, ray, v.on_surface, hit, emission, tau, local.rays);
                radiance += throughput * in;
                break;
            }
            radiance += throughput * seen_through(scene_, ray, v.on_surface, hit, emission, local.profile, local.rays);
            if (gathers) radiance += throughput * beam_in_scattering(ray, t_end, rng);
            break;
        }
        if (v.escaped()) {
            radiance += throughput * escaped_radiance(scene_, ray.dir, emission);
            if (march && !(max_depth >= 0 && depth + 1 > max_depth))
                radiance += throughput * march_in_scattering(ray, kInfinity, depth, rng);
            if (beam && !(max_depth >= 0 && depth + 1 > max_depth)) radiance += throughput * beam_in_scattering(ray, kInfinity, rng);
            break;
        }
        if (!event && hit.emitter) radiance += throughput * emitted_radiance(scene_, ray, hit, emission);   // black: ends below
        if (max_depth >= 0 && depth + 1 > max_depth) break;
        if (march) {
            // The medium's in-scattering along this segment comes from the march; the collision
            // sampled above only decides whether the path reaches the surface behind (probability T).
            radiance += throughput * march_in_scattering(ray, t_end, depth, rng);
            if (event) break;
        }
        if (beam) {   // the same rule with the whole segment in one query
            radiance += throughput * beam_in_scattering(ray, t_end, rng);
            if (event) break;
        }
        if (event) {
            const Vec3 x = ray.at(event.t);
            const Medium& m = *event.medium;
            const Rgb weight = throughput * m.albedo();
            if ((weight == 0.0).all()) break;
            const bool nee = settings_.direct == DirectLighting::nee;
            const double sigma_t = total_sigma_t(scene_, x);
            auto& local = threads_->local.local();
            // The query draws no random numbers, so it runs first: a path that goes on from x
            // weighs its NEE against the bounce (render.mis) like the path tracer's
            // (transport/single_scattering.h); one that ends on the map weighs it 1.
            BoundedEstimate b;
            if (sigma_t > 0.0) b = bounded_in_scattering(x, -ray.dir, m.g(), sigma_t, local.buffers, &local.stats);
            const bool goes_on = b.rule == BoundedQuery::continue_path;
            if (nee) {
                if (segment) {
                    const SegmentPoint at{&*segment, event.t, segment->free_flight_density_at(event.t, m.sigma_t(x))};
                    radiance += weight * single_scattering(x, ray.dir, m.g(), goes_on, rng, &at);
                } else {
                    radiance += weight * single_scattering(x, ray.dir, m.g(), goes_on, rng);
                }
                ++local.rays;
            }
            if (!(sigma_t > 0.0) || b.rule == BoundedQuery::zero) break;
            if (goes_on) {   // too few photons: scatter and go on
                ++local.continued;
                if (!nee) radiance += weight * direct_light_in_medium(scene_, x, ray.dir, m.g(), rng, settings_.walk.mis);
                throughput = weight;
                const double u1 = rng.uniform(), u2 = rng.uniform();
                const Vec3 wo = hg_sample(ray.dir, m.g(), u1, u2);
                emission = continued_emission(settings_.walk.mis, x, ray.dir, wo, m.g());
                ray = Ray{x, wo};
                if (!survive_roulette(throughput, depth + 1, settings_.walk.rr_depth, rng)) break;
                continue;
            }
            radiance += weight * normalised(b.estimate, x, -ray.dir, m.g(), b.radius, sigma_t, local.buffers, local.linear_weights) /
                        region_share(x, b.estimate.radius);
            ++local.map_used;
            break;
        }
        if (hit.specular) {   // mirror or glass (transport/specular_step.h): on to the chain's next vertex
            if (!camera_specular_step(hit, ray, throughput, emission, depth + 1, settings_.walk.rr_depth, rng)) break;
            region = region_after_specular(region, hit, ray.dir);
            continue;
        }
        if ((hit.reflectance == 0.0).all()) break;
        // The surface photon map gives the light the path would gather. A map of fewer than k photons
        // (empty or starved) has no kNN disc anywhere: the path goes on as under final_gather.
        const PhotonMap* surface_map = surface_map_here();
        if (surface_map && surface_map->size() >= k_) {
            if (settings_.direct == DirectLighting::nee) radiance += throughput * direct_light_on_surface(scene_, hit, rng);
            auto& local = threads_->local.local();
            const Estimate<Rgb> e = estimate_surface_irradiance(*surface_map, hit.position, hit.normal,
                                                                surface_estimator_, k_, max_radius_, local.buffers, &local.surface_stats);
            radiance += throughput * hit.reflectance * (e.value / kPi);
            ++local.map_used;
            break;
        }
        radiance += throughput * direct_light_on_surface(scene_, hit, rng, settings_.walk.mis);
        throughput *= hit.reflectance;
        ray = diffuse_bounce(hit, rng);
        emission = EmissionWeighting::after(settings_.walk.mis, hit.position, std::max(0.0, ray.dir.dot(hit.normal)) * kInvPi);
        if (!survive_roulette(throughput, depth + 1, settings_.walk.rr_depth, rng)) break;
    }
    return radiance;
}

Rgb PhotonMapIntegrator::normalised(const Estimate<Rgb>& s, const Vec3& x, const Vec3& w_o, double g, double max_radius,
                                    double sigma_t, GatherBuffers& buffers, std::vector<Rgb>& scratch) const {
    // S estimates sigma_t times the incident radiance. The ball can miss every quadrature point's
    // smoke only if it is tiny; then use the point.
    if (settings_.extinction == ExtinctionNormalisation::point || !(s.radius > 0.0)) return s.value / sigma_t;
    const bool linear = settings_.extinction == ExtinctionNormalisation::linear;
    if (leaves_half_out() && s.kind == EstimateCase::knn) {
        // photon/estimate/group_estimate.h: the list was gathered with gather_count() neighbours; rarely more are needed.
        size_t found = buffers.list.size();
        const PhotonMap& map = volume_map_here();
        bool complete = found < gather_count() || found == map.size();
        for (;;) {
            const GroupEstimate e = leave_half_out(buffers, found, complete, k_, max_radius, map, x, threads_->ball, linear,
                                                   &threads_->local.local().lookups, volume_estimator_.radius_scale());
            if (e.used) {
                if (e.linear_fell_back) ++threads_->local.local().linear_fallbacks;
                return e.value;
            }
            if (e.want == 0) break;   // no finite ball for some half: the plain estimate below
            found = map.knn(x, e.want, max_radius, buffers.list);
            complete = found < e.want || found == map.size();
            if (buffers.w.size() < found) {
                buffers.w.resize(found);
                buffers.d2.resize(found);
            }
            for (size_t i = 0; i < found; ++i) {
                buffers.w[i] = hg_eval(buffers.list[i].direction.dot(w_o), g) * buffers.list[i].power;
                buffers.d2[i] = buffers.list[i].d2;
            }
        }
    }
    if (linear) {
        const BallMoments m = threads_->ball.moments(x, s.radius, &threads_->local.local().lookups);
        if (m.m0 > 0.0)
            return linear_estimate(s, volume_estimator_, buffers, volume_map_here(), x, m, scratch, &threads_->local.local().linear_fallbacks);
        return s.value / sigma_t;
    }
    const double ball = threads_->ball.mean(x, s.radius, &threads_->local.local().lookups);
    return s.value / (ball > 0.0 ? ball : sigma_t);
}

void PhotonMapIntegrator::with_fresh_counters(const std::function<void()>& f) {
    std::unique_ptr<ThreadState> run = std::move(threads_);
    threads_ = std::make_unique<ThreadState>(run->ball);
    f();
    threads_ = std::move(run);
}

CountedOperations PhotonMapIntegrator::counted_operations() const {
    CountedOperations c;
    for (const auto& l : threads_->local) {
        c.queries += double(l.stats.queries + l.surface_stats.queries + l.decisions);
        c.rays += double(l.rays);
        c.lookups += double(l.lookups);
        c.march_weight_max = std::max(c.march_weight_max, l.march_weight_max);
        c.map_used += double(l.map_used);
    }
    return c;
}

bool PhotonMapIntegrator::leaves_half_out() const { return settings_.leaves_group_out(); }

size_t PhotonMapIntegrator::gather_count() const { return leaves_half_out() ? leave_half_out_gather(k_) : k_; }

PhotonMapIntegrator::BoundedEstimate PhotonMapIntegrator::bounded_in_scattering(const Vec3& x, const Vec3& w_o, double g,
                                                                             double sigma_t, GatherBuffers& buffers,
                                                                             EstimatorStats* stats) const {
    BoundedEstimate b;
    b.radius = bounded_radius(max_radius_, settings_.max_radius_mfp, sigma_t);
    if (volume_map_starved()) {
        b.rule = BoundedQuery::continue_path;
        return b;
    }
    if (decision_map_ && b.radius < max_radius_) {
        // Decided apart (photon/estimate/bounded_radius.h): k photons of the decision map within the bound,
        // scaled to its density, and the estimate is the map's unbounded kNN estimate.
        const DecisionBall d = decision_ball(b.radius);
        if (!decision_cells_.surely_holds(x, d.radius, d.k)) {
            ++threads_->local.local().decisions;
            if (decision_map_->knn(x, d.k, d.radius, buffers.list) < d.k) {
                b.rule = BoundedQuery::continue_path;
                return b;
            }
        }
        b.radius = max_radius_;
    }
    b.estimate = estimate_in_scattering(volume_map_here(), x, w_o, g, volume_estimator_, k_, b.radius, buffers, stats, gather_count());
    if (b.radius < max_radius_) b.rule = bounded_query(b.estimate, k_);   // the mean-free-path bound is in force
    return b;
}

bool PhotonMapIntegrator::volume_map_starved() const {
    // A query needs k photons: a map of fewer than k (empty, thinned by store_probability, a tiny
    // count, or k above the stored count) has no kNN ball anywhere, bound or no bound. Without the
    // bound (max_radius_mfp = 0) estimator rule (b) would use the whole map instead, at the cost of
    // a pass over the map per query (k = 65536 over 55,265 photons ran for minutes).
    return volume_map_here().size() < k_;
}

bool PhotonMapIntegrator::marches(const Ray& ray, double t_end) const {
    switch (gather_) {
        case Gather::collision: return false;
        case Gather::march: return true;
        case Gather::beam: return false;
        case Gather::photon_beams: return false;
        case Gather::threshold: break;
    }
    // gather = "threshold" (the default before the measured plan). Thin along this segment: every ray
    // gathers at a few points. Thick: the collision gather puts its one query where the light is and
    // bounds its ball in mean free paths, while the march's points, all a few mean free paths apart,
    // would mostly take continued paths. The walk stops once the threshold is passed,
    // so thick segments, the collision gather's, pay for a few majorant pieces only.
    const double limit = settings_.march_max_optical_depth;
    double depth = 0.0;
    for (const auto& m : scene_.media) {
        m->majorant_pieces(ray, t_end, [&](double ta, double tb, double mu) {
            depth += mu * (tb - ta);
            return depth <= limit;
        });
        if (depth > limit) return false;
    }
    return true;
}

Rgb PhotonMapIntegrator::march_in_scattering(const Ray& ray, double t_end, int depth, Rng& rng, double* optical_depth) const {
    // Per medium, m stratified points with the free-flight density of its exact extinction
    // (transport/march_points.h): each weighs albedo P / m times the other media's transmittance,
    // P = 1 - exp(-tau(t_end)), so weights stay bounded in any density field; m = n or fewer where
    // P is small (photons.march_points, transport/march_count.h).
    const int n = settings_.gather_queries;
    auto& local = threads_->local.local();
    Rgb sum = Rgb::Zero();
    // With direct = "nee" every point takes NEE: point and spot lights are also sampled equiangularly
    // along the segment, each point's NEE to them weighted with the march's density there.
    std::optional<EquiangularSegment> segment;
    std::vector<MarchMass> masses;
    if (settings_.walk.equiangular && settings_.direct == DirectLighting::nee) {
        segment.emplace(scene_, ray, t_end);
        if (segment->empty())
            segment.reset();
        else
            masses.assign(scene_.media.size(), MarchMass{});
    }
    // The profile counts as one tracked segment per point, like each other medium's.
    for_each_march_point(scene_, ray, t_end, n, settings_.march_points, rng, scene_.media.size(), local.rays,
                         [&](const Medium& medium, double t, double others, MarchMass mass) {
                             // Relative to the weight in the medium alone.
                             local.march_weight_max = std::max(local.march_weight_max, others);
                             local.march_weight_sum += others;
                             ++local.march_points;
                             const Vec3 x = ray.at(t);
                             const Rgb weight = (others * mass.mass / mass.divisor) * medium.albedo();
                             if (!segment) {
                                 sum += weight * incident_at_march_point(x, ray.dir, medium.g(), total_sigma_t(scene_, x), weight, depth, rng);
                                 return;
                             }
                             const double tau = segment->medium_depth(segment->medium_index(medium), t);
                             const SegmentPoint at{&*segment, t, march_density(mass, medium.sigma_t(x), tau)};
                             sum += weight * incident_at_march_point(x, ray.dir, medium.g(), total_sigma_t(scene_, x), weight,
                                                                     depth, rng, &at);
                         },
                         optical_depth, segment ? masses.data() : nullptr);
    if (segment)
        sum += segment->in_scattering(rng, local.rays, [&](size_t i, double sigma_t, double tau_m, double) {
            return march_density(masses[i], sigma_t, tau_m);
        });
    return sum;
}

Rgb PhotonMapIntegrator::incident_at_march_point(const Vec3& x, const Vec3& dir, double g, double sigma_t,
                                                 const Rgb& weight, int depth, Rng& rng, const SegmentPoint* at) const {
    const bool nee = settings_.direct == DirectLighting::nee;
    Rgb in = Rgb::Zero();   // phase-weighted incident radiance at x
    auto& local = threads_->local.local();
    // The collision gather's bound and rule (photon/estimate/bounded_radius.h) here: a ball spanning many mean
    // free paths averages the lit skin of a dense medium with its dark inside (biased low), so where
    // fewer than k photons lie within the bound the point takes the light a path would find instead,
    // NEE and one phase-sampled continuation, both unbiased for the same incident radiance; where
    // exactly k - 1 do, it takes 0, whose mass the k-1 correction already counts on the kNN side.
    // The choice depends on x and the map only; the query draws no random numbers, so NEE, weighted
    // as transport/single_scattering.h says, follows it.
    const BoundedEstimate b = bounded_in_scattering(x, -dir, g, sigma_t, local.buffers, &local.stats);
    const bool wide = b.rule == BoundedQuery::continue_path;
    if (nee) {
        in += single_scattering(x, dir, g, wide, rng, at);
        ++local.rays;
    }
    if (b.rule == BoundedQuery::zero) return in;
    if (wide) {
        ++local.march_wide;
        if (!nee) in += direct_light_in_medium(scene_, x, dir, g, rng, settings_.walk.mis);
        ++local.rays;
        // Roulette on the point's weight: where it is small, so is the chance of paying for a path.
        const double q = std::min(1.0, weight.maxCoeff());
        if (rng.uniform() < q) {
            const double u1 = rng.uniform(), u2 = rng.uniform();
            const Vec3 wo = hg_sample(dir, g, u1, u2);
            in += trace(Ray{x, wo}, depth + 1, rng, continued_emission(settings_.walk.mis, x, dir, wo, g)) / q;
        }
        return in;
    }
    ++local.map_used;
    return in + normalised(b.estimate, x, -dir, g, b.radius, sigma_t, local.buffers, local.linear_weights) /
                    region_share(x, b.estimate.radius);
}

void PhotonMapIntegrator::retire_beam() {
    if (!beam_) return;
    const BeamGatherStats b = beam_->stats();
    beam_before_.radii_seconds += b.radii_seconds;
    beam_before_.bvh_seconds += b.bvh_seconds;
    beam_before_.queries += b.queries;
    beam_before_.crossed += b.crossed;
    beam_before_.tracking_lookups += b.tracking_lookups;
    beam_.reset();
}

void PhotonMapIntegrator::build_beam(std::ostream* log, RunStats* stats) {
    retire_beam();
    beam_ = std::make_unique<BeamGather>(scene_, *map_, size_t(settings_.beam_k), settings_.estimator.kernel(), max_radius_,
                                         settings_.max_radius_mfp, beam_scale_);
    const BeamGatherStats b = beam_->stats();
    if (stats) {
        stats->phase("build_radii", b.radii_seconds);
        stats->phase("build_beam_bvh", b.bvh_seconds);
    }
    // A map of at most beam_k photons has no disc: its segments gather like "march", whose points
    // take NEE and a continued path where the map is starved (unbiased, and every segment still
    // gets its single scattering by NEE, as the beam's would).
    gather_ = beam_->usable() ? Gather::beam : Gather::march;
    if (log) {
        *log << "beam: radii (beam_k = " << b.k << ") " << b.radii_seconds << " s, BVH over " << b.photons << " discs "
             << b.bvh_seconds << " s; " << b.total_bytes_per_photon << " bytes/photon (map " << b.map_bytes_per_photon
             << " + BVH " << b.bvh_bytes_per_photon << ")\n";
        if (!beam_->usable() && scene_.has_media())
            *log << "warning: photons.beam_k = " << b.k << " is not below the " << map_->size()
                 << " volume photons stored: no photon has a beam_k-th neighbour, so this pass gathers like \"march\"\n";
    }
}

void PhotonMapIntegrator::retire_photon_beams() {
    if (!photon_beams_) return;
    const PhotonBeamGatherStats b = photon_beams_->stats();
    photon_beams_before_.widths_seconds += b.widths_seconds;
    photon_beams_before_.bvh_seconds += b.bvh_seconds;
    photon_beams_before_.queries += b.queries;
    photon_beams_before_.crossed += b.crossed;
    photon_beams_before_.tested += b.tested;
    photon_beams_before_.starved += b.starved;
    photon_beams_before_.tracking_lookups += b.tracking_lookups;
    photon_beams_.reset();
}

void PhotonMapIntegrator::build_photon_beams(std::ostream* log, RunStats* stats) {
    retire_photon_beams();
    photon_beams_ = std::make_unique<PhotonBeamGather>(scene_, std::move(owned_.beams), settings_.beam_widths, k_,
                                                       std::string(settings_.estimator.name()) == "classic",
                                                       settings_.estimator.kernel(), max_radius_);
    owned_.beams.clear();
    const PhotonBeamGatherStats b = photon_beams_->stats();
    if (stats) {
        if (settings_.beam_widths == BeamWidths::sample_point) stats->phase("build_beam_widths", b.widths_seconds);
        stats->phase("build_photon_beam_bvh", b.bvh_seconds);
    }
    // No beam at all (no media, or every flight outside them): the segments gather like "march".
    gather_ = photon_beams_->usable() ? Gather::photon_beams : Gather::march;
    if (log) {
        *log << "photon_beams: " << b.beams << " beams, widths \"" << b.widths << "\" (k = " << b.k << ", "
             << settings_.estimator.label() << " in 1D)";
        if (settings_.beam_widths == BeamWidths::sample_point) *log << ", widths " << b.widths_seconds << " s";
        *log << ", BVH " << b.bvh_seconds << " s, " << b.bytes_per_beam << " bytes/beam\n";
        if (!photon_beams_->usable() && scene_.has_media())
            *log << "warning: no photon beam was recorded in the media, so this pass gathers like \"march\"\n";
    }
}

Rgb PhotonMapIntegrator::beam_in_scattering(const Ray& ray, double t_end, Rng& rng) const {
    Rgb l = gather_ == Gather::photon_beams ? photon_beams_->in_scattering(ray, t_end, rng) : beam_->in_scattering(ray, t_end, rng);
    if (settings_.direct == DirectLighting::nee)
        l += segment_direct_light(scene_, ray, t_end, settings_.gather_queries, rng, threads_->local.local().rays,
                                  settings_.walk.equiangular);
    return l;
}

void PhotonMapIntegrator::choose_gather(const PassContext& context) {
    // Work units per counted operation, in nanoseconds of this machine's single-thread figures
    // (docs/studies/photon_map_structure.md section 1, photon_tracing.md section 3): a kNN query 700 + 280 k (bench_photon_map: 2.9 us at k = 8,
    // 8.3 at k = 32, 37 at k = 128), a tracked segment 1000 in grids (about one real collision
    // of delta tracking plus the DDA) and 100 in homogeneous media (closed forms), a sigma_t
    // lookup of the ball quadrature 50. Only their ratios matter, and only between candidates
    // whose variance x cost differ by less than the error of these weights.
    bool grids = false;
    for (const auto& m : scene_.media) grids = grids || !dynamic_cast<const HomogeneousMedium*>(m.get());
    const double w_query = 700.0 + 280.0 * double(k_), w_ray = grids ? 1000.0 : 100.0, w_lookup = 50.0;
    constexpr int kSide = 8, kSamples = 16;
    constexpr int kRays = kSide * kSide;
    const Gather candidates[] = {Gather::collision, Gather::march, Gather::threshold};
    GatherPilotStats pilot = pilot_ ? *pilot_ : GatherPilotStats{};
    pilot.candidates = {"collision", "march", "auto"};
    pilot.variance.assign(3, 0.0);
    pilot.cost.assign(3, 0.0);

    // The pilot's queries are not the run's: its counters are put back afterwards.
    struct Counts {
        EstimatorStats stats, surface_stats;
        uint64_t continued, march_wide, rays, lookups;
        double weight_max, weight_sum;
        uint64_t points;
    };
    std::map<const ThreadState::Local*, Counts> saved;
    for (auto& l : threads_->local)
        saved[&l] = {l.stats, l.surface_stats, l.continued, l.march_wide, l.rays, l.lookups, l.march_weight_max, l.march_weight_sum, l.march_points};
    auto totals = [&](uint64_t& queries, uint64_t& rays, uint64_t& lookups) {
        queries = rays = lookups = 0;
        for (const auto& l : threads_->local) {
            queries += l.stats.queries + l.surface_stats.queries;
            rays += l.rays;
            lookups += l.lookups;
        }
    };
    const Camera& camera = scene_.camera;
    const uint64_t seed = mix64(context.seed ^ 0x70696c6f74ULL);   // streams apart from the camera pass's
    std::vector<double> variance(kRays);
    int chosen = 0;
    for (int c = 0; c < 3; ++c) {
        gather_ = candidates[c];
        uint64_t q0, r0, l0, q1, r1, l1;
        totals(q0, r0, l0);
        tbb::parallel_for(0, kRays, [&](int j) {
            Rng rng(seed, context.stream_offset * uint64_t(kRays) + uint64_t(j));
            double mean = 0.0, m2 = 0.0;
            for (int s = 0; s < kSamples; ++s) {
                const double x = (j % kSide + rng.uniform()) / kSide * camera.width();
                const double y = (j / kSide + rng.uniform()) / kSide * camera.height();
                const Rgb l = trace(camera.generate_ray(x, y), 0, rng);
                const double v = all_finite(l) ? 0.2126 * l[0] + 0.7152 * l[1] + 0.0722 * l[2] : 0.0;
                const double d = v - mean;
                mean += d / (s + 1);
                m2 += d * (v - mean);
            }
            variance[size_t(j)] = m2 / (kSamples - 1);
        });
        totals(q1, r1, l1);
        double v = 0.0;
        for (double x : variance) v += x;
        pilot.variance[size_t(c)] = v / kRays;
        pilot.cost[size_t(c)] = (w_query * double(q1 - q0) + w_ray * double(r1 - r0) + w_lookup * double(l1 - l0)) / (kRays * kSamples);
    }
    // Least variance x cost; with no variance anywhere (nothing lit in view), least cost.
    for (int c = 1; c < 3; ++c) {
        const double a = pilot.variance[size_t(c)] * pilot.cost[size_t(c)];
        const double b = pilot.variance[size_t(chosen)] * pilot.cost[size_t(chosen)];
        if (a < b || (a == b && pilot.cost[size_t(c)] < pilot.cost[size_t(chosen)])) chosen = c;
    }
    gather_ = candidates[chosen];
    pilot.chosen = pilot.candidates[size_t(chosen)];
    pilot.chosen_count.resize(3, 0);
    ++pilot.chosen_count[size_t(chosen)];
    pilot_ = pilot;
    for (auto& l : threads_->local) {
        const auto it = saved.find(&l);
        const Counts k = it != saved.end() ? it->second : Counts{};
        l.stats = k.stats;
        l.surface_stats = k.surface_stats;
        l.continued = k.continued;
        l.march_wide = k.march_wide;
        l.rays = k.rays;
        l.lookups = k.lookups;
        l.march_weight_max = k.weight_max;
        l.march_weight_sum = k.weight_sum;
        l.march_points = k.points;
    }
    if (context.log && context.first_of_run) {
        *context.log << "gather: the pilot chose \"" << pilot.chosen << "\" (pilot, " << kRays << " rays x " << kSamples
                     << " samples: variance x cost";
        for (int c = 0; c < 3; ++c)
            *context.log << (c ? ", " : " ") << pilot.candidates[size_t(c)] << " " << pilot.variance[size_t(c)] * pilot.cost[size_t(c)];
        *context.log << ")\n";
    }
}

namespace {

struct PhotonMapIntegratorSettings : IntegratorSettings {
    PhotonMapSettings settings;
    std::unique_ptr<Integrator> create(const Scene& scene) const override {
        return std::make_unique<PhotonMapIntegrator>(scene, settings);
    }
};

}  // namespace

std::unique_ptr<IntegratorSettings> read_photon_map_settings(Params& render, Params& root) {
    auto s = std::make_unique<PhotonMapIntegratorSettings>();
    Params photons = root.table("photons");
    s->settings = PhotonMapSettings::read(render, photons);
    photons.finish();
    return s;
}

std::unique_ptr<IntegratorSettings> read_auto_integrator_settings(Params& render, Params& root) {
    auto s = std::make_unique<PhotonMapIntegratorSettings>();
    Params photons = root.table("photons");
    s->settings = PhotonMapSettings::read(render, photons, true);
    photons.finish();
    // The plan chooses between the path tracer and the map's collision or march gather: a gather
    // that is chosen otherwise ("pilot", "threshold", "beam") cannot be honoured with it.
    const GatherMode g = s->settings.gather;
    if (render.string("integrator", "path") == "auto" && g != GatherMode::automatic && g != GatherMode::collision &&
        g != GatherMode::march)
        photons.fail("gather", "render.integrator = \"auto\" chooses between the path tracer and the photon map's "
                               "\"collision\" or \"march\" gather: photons.gather must be \"auto\", \"collision\" or "
                               "\"march\" with it (or set render.integrator = \"photon_map\")");
    return s;
}

const PhotonMapSettings& photon_map_settings(const RunConfig& config) {
    return static_cast<const PhotonMapIntegratorSettings&>(config.settings_for("photon_map")).settings;
}

}  // namespace vpm
