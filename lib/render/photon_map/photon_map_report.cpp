// What a photon-map run reports (PhotonMapIntegrator::collect): what ran, the photons traced per
// phase, the estimates by case, the schedule's radii, the automatic choices and the gathers' counts,
// into the run's statistics and its log.
#include <ostream>
#include <string>

#include "render/photon_map/gathers/segment_gather.h"
#include "render/photon_map/photon_map_integrator.h"
#include "render/photon_map/photon_map_stats.h"

namespace vpm {

void PhotonMapIntegrator::collect(RunStats& stats, std::ostream* log) const {
    stats.integrator_used = integrator_used();
    stats.gather_used = gather_used();
    const CameraTotals t = totals();
    stats.map_estimates = t.map_used;
    PhotonMapStats& pm = PhotonMapStats::in(stats);
    if (maps_.owns) {
        PhotonLedger l = photons_.ledger;
        l.estimates = *stats.map_estimates;
        l.decision_queries = decision_.map() ? t.estimates.decisions : 0;
        pm.photon_ledger = l;
        if (log)
            *log << "photons traced per phase: " << l.pass_maps << " in " << l.passes_traced << " passes' maps ("
                 << l.estimates << " estimates taken from them), " << l.pilot_only << " for the pilot alone, " << l.probe
                 << " in the probe that sized the pilot's map, " << l.decision_map << " in the decision map ("
                 << l.decision_queries << " radius decisions queried it)\n";
    }
    pm.volume_estimates = t.estimates.stats;
    if (!radii_log_.radii.empty()) {
        PassRadiiStats r = radii_log_;
        r.schedule = settings_.schedule == KSchedule::fixed ? "fixed" : settings_.schedule == KSchedule::shrink ? "shrink" : "progressive";
        r.alpha_points = settings_.alpha_for(3);
        r.alpha_surfaces = settings_.alpha_for(2);
        r.last = settings_.radii_for_pass(r.last_pass, scene_.has_media(), maps_.surface != nullptr || traces_surface_map());
        pm.pass_radii = r;
    }
    if (choice_.pilot) pm.gather_pilot = choice_.pilot;
    if (choice_.auto_stats) pm.auto_gather = choice_.auto_stats;
    pm.continued_paths = t.continued;
    if (settings_.extinction == ExtinctionNormalisation::linear) {
        const uint64_t fallbacks = t.estimates.linear_fallbacks;
        pm.linear_fallbacks = fallbacks;
        if (fallbacks && log)
            *log << "linear: " << fallbacks << " of " << pm.volume_estimates->queries << " estimates fell back to the "
                 << "ball normalisation (their linear-corrected sum was negative; photon/estimate/linear_estimate.h)\n";
    }
    if (settings_.extinction == ExtinctionNormalisation::linear_signed) {
        const uint64_t negatives = t.estimates.linear_fallbacks;
        pm.linear_negatives = negatives;
        if (negatives && log)
            *log << "linear_signed: " << negatives << " of " << pm.volume_estimates->queries
                 << " estimates were negative and kept (unbiased; the image may hold negative pixels)\n";
    }
    if (decision_.map()) pm.decision_queries = t.estimates.decisions;
    if (log)
        *log << "estimates: " << pm.volume_estimates->to_string() << "; camera paths continued past a collision "
             << "(fewer than k photons within photons.max_radius_mfp, or in the map): " << *pm.continued_paths
             << (decision_.map() ? "; decision map queries: " + std::to_string(*pm.decision_queries) : std::string()) << "\n";
    if (settings_.gather != GatherMode::collision) {
        const uint64_t wide = t.march_wide;
        pm.march_wide_queries = wide;
        if (t.march_points > 0) {
            pm.march_weight_max = t.march_weight_max;
            pm.march_weight_mean = t.march_weight_sum / double(t.march_points);
        }
        if (wide > 0 && log)
            *log << "march: " << wide << " march points took NEE and a continued path instead of an estimate (a kNN "
                 << "ball wider than photons.max_radius_mfp = " << settings_.max_radius_mfp
                 << " mean free paths, or fewer than k = " << pass_.k << " photons in the map); "
                 << pm.volume_estimates->queries << " map queries in all\n";
    }
    if (segment_gather_) segment_gather_->add_to(stats, log);
    const EstimatorStats& ss = t.surface_stats;
    if (ss.queries) {
        pm.surface_estimates = ss;
        if (log) *log << "surface estimates: " << ss.to_string() << "\n";
    }
}

}  // namespace vpm
