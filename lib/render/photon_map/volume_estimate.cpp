#include "render/photon_map/volume_estimate.h"

#include <algorithm>
#include <cmath>

#include "core/henyey_greenstein.h"
#include "photon/estimate/group_estimate.h"
#include "photon/estimate/linear_estimate.h"

namespace vpm {

namespace {

// The fewest decision-map photons a decision counts: a smaller count decides by its noise.
constexpr size_t kDecisionMinK = 4;

}  // namespace

void EstimateCounts::merge(const EstimateCounts& o) {
    stats.merge(o.stats);
    decisions += o.decisions;
    lookups += o.lookups;
    linear_fallbacks += o.linear_fallbacks;
}

VolumeEstimate VolumeEstimator::estimate(const Vec3& x, const Vec3& w_o, double g, double sigma_t,
                                         EstimateScratch& scratch, EstimateCounts& counts) const {
    VolumeEstimate result;
    if (starved()) {
        result.rule = BoundedQuery::continue_path;
        return result;
    }
    double bound = bounded_radius(max_radius, max_radius_mfp, sigma_t);
    GatherBuffers& buffers = scratch.buffers;
    if (decision.map && bound < max_radius) {
        // k photons of the decision map within the bound, scaled to its density; the estimate is then
        // the map's unbounded kNN estimate.
        const DecisionBall d = decision_ball(bound);
        if (!decision.cells->surely_holds(x, d.radius, d.k)) {
            ++counts.decisions;
            if (decision.map->knn(x, d.k, d.radius, buffers.list) < d.k) {
                result.rule = BoundedQuery::continue_path;
                return result;
            }
        }
        bound = max_radius;
    }
    const Estimate<Rgb> s = neighbourhood == Neighbourhood::walks
                                ? estimate_in_scattering_walks(map, x, w_o, g, estimator, k, bound, buffers, &counts.stats)
                                : estimate_in_scattering(map, x, w_o, g, estimator, k, bound, buffers, &counts.stats, gather_count());
    if (bound < max_radius) result.rule = bounded_query(s, k);   // the mean-free-path bound is in force
    if (result.rule == BoundedQuery::use_estimate) {
        result.incident = normalised(s, x, w_o, g, bound, sigma_t, scratch, counts);
        // The ball's share in x's region: the extinction of a region query counts it already.
        if (interfaces && !(region_extinction() && uses_ball_extinction(s)))
            result.incident /= region_ball_fraction(interfaces, x, s.radius, region);
    }
    return result;
}

VolumeEstimator::DecisionBall VolumeEstimator::decision_ball(double radius) const {
    // The map's k photons within R, in the decision map's density: k N_d / N photons expected within
    // R, at least kDecisionMinK of them, within the ball that holds that many on average.
    DecisionBall d;
    d.k = std::min(k, std::max(kDecisionMinK, size_t(std::lround(double(k) / decision.ratio))));
    d.radius = radius * std::cbrt(double(d.k) / double(k) * decision.ratio);
    return d;
}

bool VolumeEstimator::region_extinction() const { return interfaces && ball.has_interior_media(); }

bool VolumeEstimator::uses_ball_extinction(const Estimate<Rgb>& s) const {
    return extinction != ExtinctionNormalisation::point && s.radius > 0.0;
}

size_t VolumeEstimator::gather_count() const { return leave_group_out ? leave_half_out_gather(k) : k; }

Rgb VolumeEstimator::normalised(const Estimate<Rgb>& s, const Vec3& x, const Vec3& w_o, double g, double bound,
                                double sigma_t, EstimateScratch& scratch, EstimateCounts& counts) const {
    // S estimates sigma_t times the incident radiance. The ball can miss every quadrature point's
    // smoke only if it is tiny; then use the point.
    if (extinction == ExtinctionNormalisation::point || !(s.radius > 0.0)) return s.value / sigma_t;
    const bool linear = extinction == ExtinctionNormalisation::linear || extinction == ExtinctionNormalisation::linear_signed;
    const BallRegion in_region{interfaces, region};
    const BallRegion* query_region = region_extinction() ? &in_region : nullptr;
    GatherBuffers& buffers = scratch.buffers;
    if (leave_group_out && s.kind == EstimateCase::knn) {
        // The list was gathered with gather_count() neighbours; rarely more are needed.
        size_t found = buffers.list.size();
        bool complete = found < gather_count() || found == map.size();
        for (;;) {
            const GroupEstimate e = leave_half_out(buffers, found, complete, k, bound, map, x, ball, linear,
                                                   &counts.lookups, estimator.radius_scale(), query_region);
            if (e.used) {
                if (e.linear_fell_back) ++counts.linear_fallbacks;
                return e.value;
            }
            if (e.want == 0) break;   // no finite ball for some half: the plain estimate below
            found = map.knn(x, e.want, bound, buffers.list);
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
        const BallMoments m = ball.moments(x, s.radius, &counts.lookups, query_region);
        if (m.m0 > 0.0)
            return linear_estimate(s, estimator, buffers, map, x, m, scratch.linear_weights, &counts.linear_fallbacks,
                                   extinction == ExtinctionNormalisation::linear_signed);
        return s.value / (query_region ? sigma_t * region_ball_fraction(interfaces, x, s.radius, region) : sigma_t);
    }
    const double mean = ball.mean(x, s.radius, &counts.lookups, query_region);
    if (query_region && !(mean > 0.0)) return s.value / (sigma_t * region_ball_fraction(interfaces, x, s.radius, region));
    return s.value / (mean > 0.0 ? mean : sigma_t);
}

}  // namespace vpm
