// A photons.count pinned under render.time_limit, checked against the limit before the trace
// (PhotonMapIntegrator::check_pinned_count_fits).
#include <cmath>
#include <sstream>

#include "core/error.h"
#include "core/progress.h"
#include "render/photon_map/photon_map_integrator.h"
#include "render/plan/pass_plan.h"
#include "render/plan/work_units.h"

namespace vpm {

// photons.count pinned under render.time_limit: the pass is traced at that count whatever the
// limit, so a probe's counted work (render/plan/work_units.h: deterministic, no clock) says before
// the trace whether its photon pass alone fits. A count the user set that counts past the limit's
// contract (time_limit_contract_seconds) is refused; one that counts past the limit is warned about
// (log and sidecar). Both name the count that would fit.
void PhotonMapIntegrator::check_pinned_count_fits(const PassContext& context, size_t k, RunStats& stats) {
    const Timer probe_timer;
    const PilotPhotonCount p = pilot_photon_count(scene_, settings_, context, traces_surface_map(), photons_.allocation);
    photons_.one_off_seconds += probe_timer.seconds();
    photons_.ledger.probe += uint64_t(p.probe_photons);
    const WorkUnits w = work_units(scene_, k);
    const double per_photon = photon_units(w, p);
    const double budget = settings_.time_limit * kWorkUnitsPerSecond, work = per_photon * double(settings_.count);
    if (!(work > budget)) return;
    const bool refused = settings_.count_given && work > time_limit_contract_seconds(settings_.time_limit) * kWorkUnitsPerSecond;
    std::ostringstream s;
    s.precision(3);
    s << "render.time_limit = " << settings_.time_limit << " s: photons.count = " << settings_.count
      << (settings_.count_given ? " is set" : " (its default)") << ", and its photon pass alone counts " << work / kWorkUnitsPerSecond << " s of one core (a probe of "
      << p.probe_photons << " photons: " << p.collisions_per_photon << " collisions and " << p.stored_per_photon << " stored per photon), ";
    if (refused)
        s << "past the " << time_limit_contract_seconds(settings_.time_limit) << " s a run under this limit may take (1.2 x limit + 1 s); ";
    else
        s << "so the first pass overruns the limit; ";
    if (const double fit = std::floor(budget / per_photon); fit >= 1.0) s << "about " << fit << " photons fit";
    else s << "not one photon fits";
    if (refused) {
        s << ": set photons.count to fit, " << (settings_.plan_sizes_passes() ? "--unset photons.count for the plan to size it, " : "")
          << "or raise render.time_limit";
        throw ConfigError(s.str());
    }
    // A count the plan could have sized was set by the user; for the other gathers it may be the default.
    if (settings_.plan_sizes_passes()) s << ", or leave photons.count unset for the plan to size it";
    else s << " (the plan sizes photons only for the \"collision\", \"march\", \"point_beam\" and \"photon_beams\" gathers: set photons.count to fit)";
    stats.warn(s.str(), context.log);
}

}  // namespace vpm
