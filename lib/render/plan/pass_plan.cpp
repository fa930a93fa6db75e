#include "render/plan/pass_plan.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/error.h"
#include "core/math.h"

namespace vpm {

namespace {
// A gap of 2 SE and a factor 2: rejecting a march that agrees costs little (the collision gather is
// the robust fallback); 4 SE let the plume's march through (its collision mean's SE is 1/3 of it).
constexpr double kPlanMeanSigmas = 2.0;
constexpr double kPlanMeanTolerance = 0.5;

bool means_agree(const GatherMeasurement& a, const GatherMeasurement& b) {
    const double gap = std::abs(a.mean - b.mean);
    return !(gap > kPlanMeanSigmas * std::hypot(a.mean_se, b.mean_se) &&
             gap > kPlanMeanTolerance * std::max(std::abs(a.mean), std::abs(b.mean)));
}

// Per candidate, whether its pilot mean is trusted (pass_plan.h). Where two candidates whose means
// are resolved (over kPlanMeanSigmas standard errors) agree, the candidates in such a pair are and no
// other: every candidate estimates the same image, and one that agrees with none missed a tail (or
// resolved nothing). Where no such pair exists the first candidate (the collision gather) is the
// reference, as it was for every candidate before: the means alone cannot say which one missed its
// tail. Anchored on the collision gather alone, the thin blob (optical thickness 0.1, 63 photons
// stored) trusted only the collision gather, whose 512 pilot samples held few of its rare collisions
// (mean 0.00041 +- 0.00029, against the march's 0.00142 +- 0.00032 and the continuation's
// 0.00146 +- 0.00032 over 1024 samples per pixel), and lost 9.4x to the march.
std::vector<bool> means_trusted(const std::vector<GatherMeasurement>& c) {
    auto resolved = [](const GatherMeasurement& m) { return std::abs(m.mean) > kPlanMeanSigmas * m.mean_se; };
    std::vector<bool> paired(c.size(), false);
    bool any = false;
    for (size_t i = 0; i < c.size(); ++i)
        for (size_t j = i + 1; j < c.size(); ++j)
            if (resolved(c[i]) && resolved(c[j]) && means_agree(c[i], c[j])) paired[i] = paired[j] = any = true;
    if (any) return paired;
    std::vector<bool> anchored(c.size());
    for (size_t i = 0; i < c.size(); ++i) anchored[i] = means_agree(c[i], c[0]);
    return anchored;
}
}  // namespace

double map_variance_exponent(double v_half, double v_quarter, bool& measured) {
    measured = v_half > 0.0 && v_quarter > 0.0 && std::isfinite(v_half) && std::isfinite(v_quarter);
    if (!measured) return 1.0;
    // Outside [1/3, 1] the ratio is pilot noise: no footprint makes the map's variance fall faster
    // than 1/N (independent balls) or slower than N^-1/3 (one ball across the pixel).
    return std::clamp(std::log2(v_quarter / v_half), 1.0 / 3.0, 1.0);
}

double plan_budget(const PlanInputs& in, bool pilot_map_reused) {
    if (!(in.budget > 0.0)) return 0.0;
    const double left = in.budget - in.pilot_work - (pilot_map_reused ? 0.0 : in.pilot_map_work);
    return std::max(left, 1.0);
}

namespace {

// What a pass may cost under a budget, and how far N goes below N0 for it (pass_plan.h).
struct PassSizeLimit {
    double most = kInfinity;   // work units
    int halvings = 0;          // the least N is N0 / 2^halvings
    // Not even the smallest pass fits the budget: passes no larger than the configured one (N0
    // photons, at most S0 samples) may also be planned, as the limit is no guide to their size.
    bool configured_pass = false;
};

// camera(n, s): the counted work of a camera pass of s samples per pixel over a map of n photons.
// `budget`: what the passes share (plan_budget).
template <class Camera>
PassSizeLimit pass_size_limit(const PlanInputs& in, double budget, double photon_cost, int s_lo, const Camera& camera) {
    PassSizeLimit out;
    if (!(budget > 0.0)) return out;
    const double cap = budget / kPlanMinPasses;
    auto least_n = [&] { return std::ldexp(double(in.count), -out.halvings); };
    // Halve N while the smallest pass is over the cap and its photon pass is the larger part (once
    // the camera pass is, fewer photons would shorten the pass by less than half), where a pass of
    // kPlanMinPhotons fits the budget at all.
    const double floor_n = double(kPlanMinPhotons);
    if (in.size_photons && photon_cost > 0.0 && photon_cost * floor_n + camera(floor_n, s_lo) <= budget)
        while (least_n() / 2.0 >= floor_n && photon_cost * least_n() + camera(least_n(), s_lo) > cap &&
               photon_cost * least_n() > camera(least_n(), s_lo))
            ++out.halvings;
    // A smallest pass over the cap but within the budget makes a run of about one pass: then any
    // pass within the budget serves as well, and more samples in it cost no passes.
    const double least = photon_cost * least_n() + camera(least_n(), s_lo);
    out.most = least <= cap || least > budget ? cap : budget;
    out.configured_pass = least > budget;
    return out;
}

// One candidate's best pass sizes (N photons, S samples) and their score for the variances given:
// least error^2 x time (with a budget) or variance x cost per pass.
struct Sizing {
    double score = kInfinity, cost = kInfinity;
    int64_t count = 0;
    int spp = 0;
};

// v_camera and v_map_half: the candidate's variances as read, or at their upper bounds.
Sizing size_passes(const PlanInputs& in, const GatherMeasurement& m, double v_camera, double v_map_half, double beta,
                   bool trusted) {
    v_map_half = std::max(0.0, v_map_half);   // < 0: the map's noise is below the pilot's resolution
    const double bias2_pilot = std::max(0.0, m.bias2);
    // Without the map (render/plan/no_map_candidate.h) no photon pass is made: N does not matter.
    const double photon_cost = m.uses_map ? in.photon_cost : 0.0;
    Sizing best;
    best.count = in.count;
    best.spp = in.spp;
    const int doublings = in.size_photons && m.uses_map ? kPlanMaxPhotonDoublings : 0;
    // Per doubling of the photons, each used query's price grows (the stored photons double with them).
    const double query_growth = in.query_doubling * std::min(m.per_sample.queries, m.per_sample.map_used);
    const int s_hi = in.size_samples ? kPlanMaxSpp : in.spp;
    // Without a map every sample count has the same variance x cost and ties went to 1 sample per
    // pass, whose fixed cost per pass (not counted) then dominated: the box at 1000 optical depths
    // and albedo 0.99 rendered 1366 passes of 1 sample in 2 s, 5x the path tracer's error. Such
    // passes hold at least kNoMapPassSamples camera samples, as the path tracer's groups do.
    int s_lo = in.size_samples ? 1 : in.spp;
    if (in.size_samples && !m.uses_map)
        while (s_lo < s_hi && double(s_lo) * in.pixels < kNoMapPassSamples) s_lo *= 2;
    // The map's figures were read at the pilot's photons, which may be fewer than N0.
    const double pilot = double(in.pilot_count > 0 ? in.pilot_count : in.count);
    // A query's price grows with the map's doublings over the pilot's (none counted below it).
    auto camera = [&](double n, int s) {
        return in.pixels * double(s) * (m.sample_cost + std::max(0.0, std::log2(n / pilot)) * query_growth);
    };
    // The passes share the budget less the pilot's one-off work, and less its map's photon pass
    // where no pass reuses it (N above the pilot's: pass 0 is traced again; or no map at all): the
    // limit on a pass scales alike. The run's time is the whole budget either way.
    const double budget0 = plan_budget(in, m.uses_map);
    const PassSizeLimit limit = pass_size_limit(in, budget0, photon_cost, s_lo, camera);
    for (int i = -limit.halvings; i <= doublings; ++i) {
        const double n = std::ldexp(double(in.count), i);
        const double budget = plan_budget(in, m.uses_map && n <= pilot);
        const double most = budget0 > 0.0 ? limit.most * budget / budget0 : limit.most;
        const double v_map = v_map_half * std::pow(0.5 * pilot / n, beta);
        const double bias2 = bias2_pilot * std::pow(pilot / n, 4.0 / 3.0);
        for (int s = s_lo; s <= s_hi; s *= 2) {
            const double cost = photon_cost * n + camera(n, s);
            // The smallest pass always counts, however long: a pass is not cut short.
            if (cost > most && !(i == -limit.halvings && s == s_lo) && !(limit.configured_pass && i == 0 && s <= in.spp))
                continue;
            const double variance = v_map + v_camera / double(s);
            double score = variance * cost;
            // Whole passes: P = floor(T / C) of them fit (one at least), so a pass that fills most of
            // the budget is one pass, whose variance does not average down (a 1-sample pass whose
            // photons took the budget won over 16 samples when P was taken as T / C).
            if (budget > 0.0)
                score = cost <= budget ? (variance / std::floor(budget / cost) + bias2) * in.budget
                                       : (variance + bias2) * (in.budget - budget + cost);
            if (!trusted) score = kInfinity;
            // Without the map every S scores alike (V_camera / S times S samples' cost, up to
            // rounding): then the smallest pass, which the run loop groups (render/run/run.cpp: a
            // stateless integrator's passes go in groups of at least kMinGroupSamples), so that a
            // time limit cuts it finely. (The largest, as before, left 256-sample passes that
            // ended up to a pass before the limit: 7.2 s of 8 in a 64x64 image.)
            const bool tie = m.uses_map || !(best.score < kInfinity) ? score == best.score
                                                                    : std::abs(score - best.score) <= 1e-9 * best.score;
            if ((score < best.score && !tie) || (tie && cost < best.cost)) {
                best.score = score;
                best.cost = cost;
                best.count = int64_t(n);
                best.spp = s;
            }
            if (!in.size_samples) break;
        }
    }
    return best;
}

// Per candidate, whether the plan may choose it on its figures: its march weights bounded, its
// mean trusted (means_trusted), measured beyond its probe and not excluded.
std::vector<bool> candidates_trusted(const std::vector<GatherMeasurement>& candidates) {
    std::vector<bool> trusted = means_trusted(candidates);
    for (size_t c = 0; c < candidates.size(); ++c) {
        const GatherMeasurement& m = candidates[c];
        trusted[c] = trusted[c] && !(m.max_weight > kPlanMaxMarchWeight) && !m.dropped && !m.excluded;
    }
    return trusted;
}

// The map variance at N/2 a candidate is chosen on: its upper bound (kPlanVarianceSigmas).
double upper_map_variance(const GatherMeasurement& m) {
    return std::max(0.0, m.v_map_half) + kPlanVarianceSigmas * m.v_map_half_se;
}

}  // namespace

PassPlan plan_passes(const PlanInputs& in) {
    if (in.candidates.empty()) throw Error("plan_passes: no candidate gathers");
    if (!(in.count >= 1) || !(in.spp >= 1) || !(in.pixels > 0.0))
        throw Error("plan_passes: photons.count, samples per pass and pixels must be positive");
    PassPlan plan;
    plan.count = in.count;
    plan.spp = in.spp;
    double best = kInfinity, best_cost = kInfinity;
    const std::vector<bool> trusted = candidates_trusted(in.candidates);
    for (size_t c = 0; c < in.candidates.size(); ++c) {
        const GatherMeasurement& m = in.candidates[c];
        bool measured = false;
        const double beta = map_variance_exponent(m.v_map_half, m.v_map_quarter, measured);
        // Chosen on its variances at their upper bounds (pass_plan.h: kPlanVarianceSigmas).
        const Sizing bound = size_passes(in, m, m.v_camera * (1.0 + kPlanVarianceSigmas * m.v_camera_rel_se),
                                         upper_map_variance(m), beta, trusted[c]);
        plan.score.push_back(bound.score);
        if (m.stopped_early) continue;   // scored for the record, not a choice
        // Least score; equal scores (nothing lit: every variance 0; or no candidate trusted) go to the cheaper pass.
        if (bound.score < best || (bound.score == best && bound.cost < best_cost)) {
            best = bound.score;
            best_cost = bound.cost;
            plan.chosen = int(c);
            plan.beta = beta;
            plan.beta_measured = measured;
        }
    }
    // Sized on the variance read: the bound only guards the choice between candidates.
    const GatherMeasurement& chosen = in.candidates[size_t(plan.chosen)];
    const Sizing sized = size_passes(in, chosen, chosen.v_camera, chosen.v_map_half, plan.beta, trusted[size_t(plan.chosen)]);
    plan.count = sized.count;
    plan.spp = sized.spp;
    return plan;
}

double score_at_camera_variance(const PlanInputs& in, size_t c, double v_camera) {
    const GatherMeasurement& m = in.candidates.at(c);
    bool measured = false;
    const double beta = map_variance_exponent(m.v_map_half, m.v_map_quarter, measured);
    return size_passes(in, m, v_camera, upper_map_variance(m), beta, true).score;
}

}  // namespace vpm
