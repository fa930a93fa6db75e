#pragma once
// Photons per pass N, camera samples per pass S and the gather, chosen from measurements
// (render/plan/map_noise_pilot.h) instead of fixed settings. With P passes the image's error is about
//
//     error^2 = (V_map(N) + V_camera / S) / P + bias(N)^2,
//
// each term relative, a pixel's weighted by 1 / (R^2 + 0.01) (render/plan/relative_error.h: the error is
// the relMSE per pixel the renderer is judged by). V_camera the per-sample variance of a pixel given
// the map, V_map(N) the variance of a pixel's mean that comes from the map itself (shared by every sample of a pass, so it falls with N and P
// only). A pass costs C(N, S) = c_photon N + pixels S c_sample in counted work units, so for a
// fixed time the error^2 x time to minimise is (V_map(N) + V_camera / S) C(N, S). V_map is measured
// at Np / 2 photons (the pilot's independent half maps; Np, the pilot map's photons, is N0 or fewer:
// render/photon_map/photon_pass.h) and extrapolated as N^-beta: beta = 1 where
// a pixel's footprint holds many kNN balls, 1/3 where one ball spans the pixel's cross-section (the
// balls then only average along the ray); measured from Np / 4 where given, else 1.
// With a budget T (render.time_limit in work units, less the pilot's one-off work: plan_budget) P = floor(T / C) whole passes fit, and the bias,
// which does not average out, enters: error^2 x time = ((V_map(N) + V_camera / S) / P + bias(N)^2) T for C <= T,
// (V_map + V_camera / S + bias^2) C for a pass longer than the budget (one pass is still made);
// bias(N)^2 = bias(Np)^2 (Np / N)^(4/3) as the pilot measures it (bias ~ r^2 ~ N^-2/3). N goes
// below the configured count N0 only where a budget's pass cannot hold N0's photon pass (kPlanMinPasses). Every input is a count, a variance or a config value: the
// plan is the same on any machine and thread count, and invariant to the scene's size (not to its
// radiance: the relMSE's 0.01 is absolute).
#include <cstdint>
#include <string>
#include <vector>

namespace vpm {

// Camera-side operations the photon map counts (per sample, or in all).
struct CountedOperations {
    double queries = 0.0;   // kNN queries
    double rays = 0.0;      // tracked segments: free flights, shadow rays, march transmittances
    double lookups = 0.0;   // sigma_t lookups of the ball quadrature
    double march_weight_max = 0.0;   // largest relative march point weight (not a count: a maximum)
    double map_used = 0.0;  // estimates taken from a photon map (volume or surface), not continued past
    double steps = 0.0;     // grid tracking steps: DDA cells and tentative collisions (scene/media/tracking_counter.h)
    double density_lookups = 0.0;   // grid point density lookups of the tracking
    double cells = 0.0;     // grid voxel cells integrated in closed form (tracking and the march's profile)
};

struct GatherMeasurement {
    std::string name;             // "collision", "march", "continue" (no map: render/plan/no_map_candidate.h)
    // Variances and bias of a pixel's luminance, relative (render/plan/relative_error.h).
    double v_camera = 0.0;        // per-sample variance of a pixel's luminance given the map
    double v_map_half = 0.0;      // variance of a pixel's mean from the map at Np / 2 (may be < 0: noise)
    double v_map_quarter = 0.0;   // the same at Np / 4 (not measured: < 0)
    double bias2 = 0.0;           // squared bias of a pixel at Np (>= 0; 0 where unresolved: render/plan/pilot_bias.h), ~ N^-4/3
    double sample_cost = 0.0;     // counted work units per camera sample
    double max_weight = 0.0;      // largest march point weight relative to an exact majorant's (0: no march)
    double mean = 0.0;            // the pilot's mean luminance over its pixels and samples (those that can vary: render/plan/pilot_pixels.h)
    double mean_se = 0.0;         // its standard error
    double tail_share = 0.0;      // share of its squared deviations in its largest 1/1024 samples (render/plan/pilot_tail.h)
    double v_camera_rel_se = 0.0; // relative standard error of the variance its pilot pixels read (render/plan/pilot_tail.h)
    double v_map_half_se = 0.0;   // standard error of v_map_half, from its pilot pixels' spread (0: not measured)
    CountedOperations per_sample; // the operations behind it
    int samples = 0;              // pilot samples per pixel and map (render/plan/pilot_budget.h)
    bool dropped = false;         // not measured beyond its probe: a pass of one sample costs more than the cap
    bool uses_map = true;         // false: no photon pass is paid for (render/plan/no_map_candidate.h)
    bool excluded = false;        // not a choice (render/plan/no_map_candidate.h: a map that goes unused)
    double bias_mean = 0.0;       // the pilot's pooled, signed bias at Np behind bias2
    double bias_se = 0.0;         // and its standard error
    bool stopped_early = false;   // its pilot stopped where it lost by far (render/plan/no_map_stop.h): not a choice
    double stop_low_score = 0.0;  // at its last stop test: its score at its camera variance's lower bound
    double stop_best_map_score = 0.0;   // and the best map candidate's score (0: not tested)
};

struct PlanInputs {
    std::vector<GatherMeasurement> candidates;
    double photon_cost = 0.0;   // counted work units per emitted photon (trace and build): a candidate that uses the map pays it
    double pixels = 0.0;
    int64_t count = 0;          // N0: photons.count
    // Np: the pilot map's photons, at which v_map_half, v_map_quarter and bias2 were read (fewer than
    // N0 where walks store many photons each: render/photon_map/photon_pass.h); 0: N0.
    int64_t pilot_count = 0;
    int spp = 1;                // S0: samples per pass as configured
    bool size_photons = false;  // false: N stays N0
    bool size_samples = false;  // false: S stays S0
    // render.time_limit in work units (kWorkUnitsPerSecond per second: one core); 0: no budget,
    // the bias term is left out and error^2 x work per pass is minimised.
    double budget = 0.0;
    // Counted work the pilot spent that no pass reuses (its camera samples, its half maps' builds,
    // photons traced for the plan alone: the probe, a map traced apart, the radius bound's decision
    // map): the passes share the budget less this (plan_budget).
    double pilot_work = 0.0;
    // The pilot map's photon pass: pass 0's map where the plan keeps N <= Np, one-off work where it
    // plans more photons (pass 0 is traced again at N), so charged to those sizes alone.
    double pilot_map_work = 0.0;
    // Work units a used kNN query costs more per doubling of the photons (render/plan/work_units.h's
    // query_price): a pass of 2^i times the pilot's photons prices each sample's used queries i times this higher.
    double query_doubling = 0.0;
};

// Work units per second of render.time_limit: a nominal single core (units are nanoseconds of one
// core of the development machine, render/plan/work_units.h). With more cores more passes fit than the
// plan assumes, which only shifts it towards variance; the plan never reads the clock.
constexpr double kWorkUnitsPerSecond = 1e9;

// The seconds a run under render.time_limit = T may take: a size the user
// pins whose counted first pass alone exceeds them on one core is refused.
inline double time_limit_contract_seconds(double limit) { return 1.2 * limit + 1.0; }

struct PassPlan {
    int chosen = 0;              // index into candidates
    int64_t count = 0;           // N
    int spp = 1;                 // S
    double beta = 1.0;           // V_map ~ N^-beta, the chosen candidate's
    bool beta_measured = false;  // false: 1 assumed (the quarter-map figure was noise or absent)
    std::vector<double> score;   // per candidate: least (V_map + V_camera / S) C over its (N, S)
};

// Largest factors over the configured sizes the plan considers (powers of two up to these).
constexpr int kPlanMaxPhotonDoublings = 6;
constexpr int kPlanMaxSpp = 256;
// Camera samples a pass without a map holds at least (render/plan/no_map_candidate.h), the path tracer's
// group size (render/run/run.cpp): a pass's fixed cost is not in the counted work.
constexpr double kNoMapPassSamples = 65536.0;
// With a budget, a planned pass costs at most budget / kPlanMinPasses work units: a pass cannot be
// cut short, and the counted units run up to 3x below the time in grids (render/plan/work_units.cpp).
// Where the smallest pass the plan may make (N0 photons, or fewer where photons are sized; 1 sample,
// or S0 where pinned) costs more, the run is about one pass: any pass within the budget may be planned,
// and where even it exceeds the budget, one no larger than the configured (N0, S0). (A cap of 1/8 of the
// budget held the dense cells, whose photon pass alone costs more, at 1 sample per pass: 4-20x
// worse than the forced gathers at 16; docs/studies/auto_plan.md section 11.7.)
constexpr double kPlanMinPasses = 2.0;
// Where photons are sized, a pass of this many fits the budget and N0's photon pass is the larger part of a
// smallest pass over budget / kPlanMinPasses, N is halved (down to this) until it fits or the camera's is.
constexpr int64_t kPlanMinPhotons = 1024;
// A gather whose march points weighed more than this (relative to an exact majorant's: 1 in
// homogeneous media) is not trusted: its weights are heavy-tailed (up to e^(tau_majorant - tau)),
// and 512 pilot samples do not see the tail that sets its variance (docs/studies/auto_plan.md section 11.7:
// the forced march lost 40-30000x to the collision gather wherever its largest weight passed 30).
constexpr double kPlanMaxMarchWeight = 8.0;
// Every candidate is scored on its camera variance plus this many of its standard errors (from
// its pilot pixels' samples, render/plan/pilot_tail.h): the figure read from 512 samples of a gather, or
// from 65536 of the continuation (render/plan/no_map_candidate.h) held by a few of them, is a lower one.
// The map's variance likewise, plus this many standard errors of its pixels' spread: read from the
// few pixels that hold it (a thin plume under a sun, bench/heldout/h16), it came out 0.18x its mean
// at one seed, where the march then took 2.9x the path tracer's time to equal error for the
// continuation's 1.05 (docs/studies/heldout_scenes.md section 30).
// Charged to the continuation alone, its cheaper samples' bound (+2-14% where light-tailed) against
// the gathers' bare figures (their bounds: +25% and more) took the march in 16 of 213 plans of the
// matrix and held-out scenes where the continuation won 6 of the 9 cells at equal time
// (docs/studies/heldout_scenes.md section 29). The bound chooses the candidate; its passes are sized on the figure
// read (on the bound a thin sphere's march took 128 samples per pass for 32: 0.16 of the path
// tracer's time to equal error for 0.10).
constexpr double kPlanVarianceSigmas = 2.0;
// Every candidate estimates the same image: one whose pilot mean differs from the others' by more
// than 2 standard errors and by more than half the larger mean is missing a tail the pilot did not
// sample, and is not trusted either (pass_plan.cpp: a candidate is trusted where its mean agrees with
// another's, both resolved; where no two agree, where it agrees with the collision gather's, one
// bounded estimate per collision). The march in the plume at 100: pilot mean 1.5e-5 against
// 0.020 +- 0.007, weights below 0.06, while at equal time its error was 200x the collision gather's;
// the collision gather in the blob at 0.1: 0.00041 +- 0.00029 against 0.0014 from the march and
// the continuation, and 9.4x the march's error at equal time.

// The work units the passes share under a budget: the budget less the pilot's one-off work
// (PlanInputs::pilot_work, and pilot_map_work unless pass 0 reuses the pilot's map: a map candidate
// at N <= Np). Where the pilot's work reaches the budget no pass fits: the result is then below
// every pass's cost (1 unit), so that the run is one pass no larger than the configured one, as under
// any budget shorter than a pass. 0 without a budget.
double plan_budget(const PlanInputs& in, bool pilot_map_reused);

// The exponent beta from V_map at Np/2 and Np/4, within [1/3, 1]; `measured` false when either
// variance is not positive (then 1).
double map_variance_exponent(double v_half, double v_quarter, bool& measured);

PassPlan plan_passes(const PlanInputs& in);

// Candidate c's score as plan_passes gives it, with its camera variance at `v_camera` (its map
// variance at its upper bound), as if its mean were trusted (render/plan/no_map_stop.h).
double score_at_camera_variance(const PlanInputs& in, size_t c, double v_camera);

}  // namespace vpm
