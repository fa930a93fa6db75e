#include "photon/trace/photon_budget.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <ostream>
#include <sstream>

#include "core/error.h"

namespace vpm {

double projected_stored_photons(const PhotonTraceProgress& p) {
    const double stored = double(p.stored) + double(p.surface_stored);
    if (p.emitted == 0) return stored;
    const double later = double(p.stored) * p.later_store_fraction + double(p.surface_stored);
    return stored + later * double(p.total - p.emitted) / double(p.emitted);
}

double projected_beams(const PhotonTraceProgress& p) {
    if (p.emitted == 0) return double(p.beams);
    return double(p.beams) * double(p.total) / double(p.emitted);
}

std::function<void(const PhotonTraceProgress&)> make_photon_pass_guard(double limit_bytes, std::ostream* log,
                                                                      double log_interval_s) {
    auto next_log = std::make_shared<double>(log_interval_s);
    return [=](const PhotonTraceProgress& p) {
        const double stored = double(p.stored) + double(p.surface_stored);
        const double projected = projected_stored_photons(p);
        const double beams = projected_beams(p);
        const double per_beam = peak_bytes_per_beam();
        const double peak = projected * kPeakBytesPerStoredPhoton + beams * per_beam;
        const double used = stored * kPeakBytesPerStoredPhoton + double(p.beams) * per_beam;
        if (peak > limit_bytes || used > limit_bytes) {
            const double emitted = double(std::max<uint64_t>(p.emitted, 1));
            const double fits = used > 0.0 ? limit_bytes / (used / emitted) : 0.0;
            // What the pass keeps: photons (kd-tree), beams (BVH), or both.
            const bool photons = stored > 0.0 || p.beams == 0, both = photons && p.beams > 0;
            std::ostringstream s;
            s.precision(3);
            s << "photons.count = " << double(p.total) << " cannot fit in memory: the first " << p.emitted << " photons";
            if (photons) s << " stored " << stored / emitted << " photons each" << (both ? " and" : "");
            if (p.beams) s << " recorded " << double(p.beams) / emitted << " photon beams each";
            s << ", so the pass would store about";
            if (photons) s << " " << projected << " photons" << (both ? " and" : "");
            if (p.beams) s << " " << beams << " photon beams";
            s << " and need about " << peak / 1e9 << " GB (";
            if (photons) s << kPeakBytesPerStoredPhoton << " bytes per stored photon while the kd-tree is built" << (both ? ", " : "");
            if (p.beams) s << per_beam << " bytes per beam with its BVH";
            s << "), more than the " << limit_bytes / 1e9 << " GB of memory; photons.count <= " << std::floor(fits) << " fits";
            throw Error(s.str());
        }
        if (log && p.emitted < p.total && p.seconds >= *next_log) {
            *next_log = p.seconds + log_interval_s;
            const double eta = p.seconds * (double(p.total) / double(p.emitted) - 1.0);
            std::ostringstream s;
            s.precision(3);
            s << "trace: " << 100.0 * double(p.emitted) / double(p.total) << "% (" << double(p.emitted) << " of "
              << double(p.total) << " photons), " << stored << " stored (projected " << projected << ", "
              << peak / 1e9 << " GB), " << p.seconds << " s, ETA " << eta << " s\n";
            *log << s.str() << std::flush;
        }
    };
}

}  // namespace vpm
