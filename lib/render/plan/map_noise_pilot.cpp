#include "render/plan/map_noise_pilot.h"

#include <algorithm>
#include <cmath>

#include <tbb/parallel_for.h>

#include "photon/map/walk_group_split.h"
#include "render/plan/pilot_bias.h"
#include "render/plan/pilot_pixels.h"
#include "render/plan/relative_error.h"
#include "render/plan/pilot_tail.h"

namespace vpm {

namespace {

double luminance_of(const Rgb& l) { return all_finite(l) ? 0.2126 * l[0] + 0.7152 * l[1] + 0.0722 * l[2] : 0.0; }

constexpr int kPixels = kPilotSide * kPilotSide;
constexpr uint64_t kLongPilotSalt = 0x6c6f6e6770696c6fULL;   // streams of samples past kPilotSamples
constexpr int kSpreadPixels = kPilotSpreadSide * kPilotSpreadSide;
constexpr uint64_t kSpreadSalt = 0x7370726561647063ULL;   // the spread samples' streams
constexpr uint64_t kBackgroundSalt = 0x6261636b67726e64ULL;   // the background cost samples' streams
// A sample's slot: fixed whatever n is (`most`: the candidate's largest n; kPilotSamples with halves).
size_t at(int j, int s, int most) { return size_t(j) * size_t(most) + size_t(s); }

// Per pixel of `pixels` (samples in slots of `most`): the mean of a's first n samples minus b's,
// squared, less the samples' share Var(a - b) / n, an unbiased figure of V_map(a) + V_map(b) there,
// times the pixel's weight (render/plan/relative_error.h). Appended to `t`.
void append_map_variance_of_difference(const std::vector<double>& a, const std::vector<double>& b, int pixels, int n,
                                       int most, const std::vector<double>& weight, std::vector<double>& t) {
    for (int j = 0; j < pixels; ++j) {
        double mean = 0.0, m2 = 0.0;
        for (int s = 0; s < n; ++s) {
            const double d = a[at(j, s, most)] - b[at(j, s, most)];
            const double delta = d - mean;
            mean += delta / (s + 1);
            m2 += delta * (d - mean);
        }
        t.push_back(weight[size_t(j)] * (mean * mean - m2 / (n - 1) / n));
    }
}

// The mean of the pixels' figures and (`se`) its standard error from their spread.
double mean_with_standard_error(const std::vector<double>& t, double& se) {
    double mean = 0.0, m2 = 0.0;
    for (size_t j = 0; j < t.size(); ++j) {
        const double delta = t[j] - mean;
        mean += delta / double(j + 1);
        m2 += delta * (t[j] - mean);
    }
    se = t.size() > 1 ? std::sqrt(m2 / double(t.size() - 1) / double(t.size())) : 0.0;
    return mean;
}

// f x a + (1 - f) x b, field by field (the largest march weight is a maximum, kept from a).
CountedOperations mixed(double f, const CountedOperations& a, const CountedOperations& b) {
    CountedOperations o = a;
    o.queries = f * a.queries + (1.0 - f) * b.queries;
    o.rays = f * a.rays + (1.0 - f) * b.rays;
    o.lookups = f * a.lookups + (1.0 - f) * b.lookups;
    o.map_used = f * a.map_used + (1.0 - f) * b.map_used;
    o.steps = f * a.steps + (1.0 - f) * b.steps;
    o.density_lookups = f * a.density_lookups + (1.0 - f) * b.density_lookups;
    o.cells = f * a.cells + (1.0 - f) * b.cells;
    return o;
}

CountedOperations per_sample(const CountedOperations& before, const CountedOperations& after, double samples) {
    CountedOperations o;
    o.queries = (after.queries - before.queries) / samples;
    o.rays = (after.rays - before.rays) / samples;
    o.lookups = (after.lookups - before.lookups) / samples;
    o.map_used = (after.map_used - before.map_used) / samples;
    o.steps = (after.steps - before.steps) / samples;
    o.density_lookups = (after.density_lookups - before.density_lookups) / samples;
    o.cells = (after.cells - before.cells) / samples;
    return o;
}

// Sum over the pilot pixels of each pixel's sample variance over its n samples (Welford), times its weight.
double summed_pixel_variance(const std::vector<double>& values, int n, int most, const std::vector<double>& weight) {
    double v = 0.0;
    for (int j = 0; j < kPixels; ++j) {
        double mean = 0.0, m2 = 0.0;
        for (int s = 0; s < n; ++s) {
            const double x = values[at(j, s, most)], delta = x - mean;
            mean += delta / (s + 1);
            m2 += delta * (x - mean);
        }
        v += weight[size_t(j)] * m2 / (n - 1);
    }
    return v;
}

// The full map's mean over the pilot pixels, its standard error, and how much of the (weighted)
// variance the largest samples hold.
void add_sample_statistics(const std::vector<double>& values, int n, int most, const std::vector<double>& weight,
                           GatherMeasurement& g) {
    double sum = 0.0;
    for (int j = 0; j < kPixels; ++j)
        for (int s = 0; s < n; ++s) sum += values[at(j, s, most)];
    g.mean = sum / double(kPixels * n);
    // Pixels differ in mean, so the SE comes from the spread of the pixel means (each of n samples).
    std::vector<double> pixel_mean(kPixels, 0.0);
    double spread = 0.0;
    for (int j = 0; j < kPixels; ++j) {
        for (int s = 0; s < n; ++s) pixel_mean[size_t(j)] += values[at(j, s, most)] / n;
        spread += (pixel_mean[size_t(j)] - g.mean) * (pixel_mean[size_t(j)] - g.mean);
    }
    g.mean_se = std::sqrt(spread / (kPixels - 1) / kPixels);
    // The share of the variance in the largest samples (render/plan/pilot_tail.h), about each pixel's mean.
    std::vector<double> squares;
    squares.reserve(size_t(kPixels * n));
    for (int j = 0; j < kPixels; ++j)
        for (int s = 0; s < n; ++s) {
            const double d = values[at(j, s, most)] - pixel_mean[size_t(j)];
            squares.push_back(weight[size_t(j)] * d * d);
        }
    g.v_camera_rel_se = mean_of_squares_relative_se(squares);
    g.tail_share = largest_squares_share(std::move(squares), kPilotTailFraction);
}

// V_map and the bias from the two half maps' samples (values[1], values[2]) beside the full map's
// (values[0]), at the pilot pixels and the spread grid.
void add_map_noise(const std::vector<std::vector<double>>& values, const std::vector<std::vector<double>>& spread_values,
                   int n, const std::vector<double>& weight, const std::vector<double>& spread_weight, GatherMeasurement& g) {
    // A map variance the pilot does not resolve is charged at its standard error, not at 0 (or
    // below): at 0 the plan saw a noiseless map and took 256 samples per pass over 1e5 photons,
    // whose map noise then set the image's error (docs/studies/auto_plan.md section 17).
    std::vector<double> t;
    append_map_variance_of_difference(values[1], values[2], kPixels, n, kPilotSamples, weight, t);
    append_map_variance_of_difference(spread_values[1], spread_values[2], kSpreadPixels, kPilotSpreadSamples,
                                      kPilotSpreadSamples, spread_weight, t);
    double se = 0.0;
    const double v = mean_with_standard_error(t, se);
    g.v_map_half = 0.5 * std::max(v, se);
    g.v_map_half_se = 0.5 * se;
    const PilotBias bias = pooled_half_map_bias(values[1], values[2], values[0], kPixels, n, kPilotSamples, weight);
    g.bias2 = bias.bias2;
    g.bias_mean = bias.mean;
    g.bias_se = bias.se;
}

// V_camera and V_map also at the centres of a 16 x 16 grid, kSpreadSamples each with every map
// (the bias stays the 8 x 8 pixels'), weighted by pixel count. The 8 x 8 centres alone missed where
// the march's camera noise lives in a sphere lit from the side (1% of the pixels, on its lit rim,
// held 75% of it: 2.0e-5 read, 1.4e-4 true), and where a thin plume holds the map's noise in a
// tenth of them, V_map read from those few pixels ranged over 0.18-2.8x its mean at seeds 1-12
// (docs/studies/heldout_scenes.md section 30). Returns the grid's samples with each map.
template <class Sample>
std::vector<std::vector<double>> spread_samples(const PilotPixels& where, const std::vector<const PhotonMap*>& maps,
                                                int candidate, MapNoisePilotHooks& hooks, uint64_t seed,
                                                uint64_t stream, const Sample& sample) {
    std::vector<std::vector<double>> spread_values;
    for (size_t m = 0; m < maps.size(); ++m) {
        hooks.use(candidate, maps[m]);
        std::vector<double>& out_m = spread_values.emplace_back(size_t(kSpreadPixels) * kPilotSpreadSamples);
        tbb::parallel_for(0, kSpreadPixels, [&](int j) {
            const auto [px, py] = where.spread[size_t(j)];
            for (int s = 0; s < kPilotSpreadSamples; ++s) {
                // The same numbers for every map: the differences are the maps'.
                Rng rng(mix64(seed ^ kSpreadSalt), stream * uint64_t(kSpreadPixels * kPilotSpreadSamples) + uint64_t(j * kPilotSpreadSamples + s));
                out_m[at(j, s, kPilotSpreadSamples)] = sample(px, py, rng);
            }
        });
    }
    return spread_values;
}

// Sum over the spread grid of each pixel's sample variance, times its weight.
double summed_spread_variance(const std::vector<double>& values, const std::vector<double>& weight) {
    static_assert(kPilotSpreadSamples == 2, "the spread's variance below is that of two samples");
    double vs = 0.0;
    for (int j = 0; j < kSpreadPixels; ++j) {
        const double a = values[at(j, 0, kPilotSpreadSamples)], b = values[at(j, 1, kPilotSpreadSamples)];
        vs += weight[size_t(j)] * 0.5 * (a - b) * (a - b);   // the unbiased variance of two samples
    }
    return vs;
}

// A background sample's counted work (the same for every candidate: it meets nothing to gather).
template <class Sample>
CountedOperations background_work(const PilotPixels& where, const PhotonMap& map, MapNoisePilotHooks& hooks,
                                  uint64_t seed, uint64_t stream, const Sample& sample) {
    if (where.background.empty()) return CountedOperations();
    hooks.use(0, &map);
    const CountedOperations before = hooks.counts();
    const int n = int(where.background.size());
    tbb::parallel_for(0, n, [&](int j) {
        Rng rng(mix64(seed ^ kBackgroundSalt), stream * uint64_t(kPixels) + uint64_t(j));
        sample(where.background[size_t(j)].first, where.background[size_t(j)].second, rng);
    });
    return per_sample(before, hooks.counts(), double(n));
}

// Samples per pilot pixel for a candidate whose probe sample cost probe_cost; spent_before: the work
// the candidates before it spent together.
int candidate_samples(const PilotBudget& budget, double probe_cost, int budget_maps, bool uses_map, double spent_before) {
    int n = budget.per_candidate > 0.0 ? pilot_samples(budget.per_candidate, probe_cost, kPixels, budget_maps, kPilotSamples)
                                       : kPilotSamples;
    if (!uses_map) {
        // Without a map a sample is cheap (no kNN query, no halves) and its tail is what decides
        // (render/plan/no_map_candidate.h): up to kNoMapPilotSamples, within its budget share, or without
        // a budget within the work the candidates before it spent together. (Capped by that work
        // under a budget too, a march made cheaper left it 348 samples in the blob at g = 0.8.)
        const double share = budget.per_candidate > 0.0 ? budget.per_candidate : spent_before;
        if (share > 0.0) n = std::max(n, pilot_samples(share, probe_cost, kPixels, 1, kNoMapPilotSamples));
    }
    return n;
}

// One candidate's pilot samples: values[m] with map m (the full map, then its halves where traced),
// n per pilot pixel in slots of `most`; spread[m] the spread grid's (map candidates only).
struct TracedSamples {
    std::vector<std::vector<double>> values, spread;
    int n = 0, most = 0;
    bool halves_too = false;
    bool stopped = false;   // stopped early (render/plan/no_map_stop.h): its pixel means set no weight
};

// Each pixel's weight in the relative error (render/plan/relative_error.h), at the pilot pixels and
// the spread grid's.
struct RelativeWeights {
    std::vector<double> pixels, spread;
};

// Per pixel of `pixels` (n samples in slots of `most`) its mean, added to `sum`.
void add_pixel_means(const std::vector<double>& values, int pixels, int n, int most, std::vector<double>& sum) {
    for (int j = 0; j < pixels; ++j) {
        double mean = 0.0;
        for (int s = 0; s < n; ++s) mean += values[at(j, s, most)];
        sum[size_t(j)] += mean / n;
    }
}

// A pixel's reference R is the mean of the candidates' pixel means (each one estimate of the same
// pixel, weighted alike whatever its samples: a candidate with many samples whose pixel holds one
// rare large sample does not set it alone), so the weights are the same for every candidate. A
// candidate whose pilot stopped early is no choice and its few samples' means the noisiest: left out,
// so that the others' figures are those they read without it.
RelativeWeights relative_weights(const std::vector<TracedSamples>& traced) {
    RelativeWeights w;
    w.pixels.assign(size_t(kPixels), 0.0);
    w.spread.assign(size_t(kSpreadPixels), 0.0);
    int at_pixels = 0, at_spread = 0;
    for (const TracedSamples& t : traced) {
        if (t.n == 0 || t.stopped) continue;   // dropped after its probe, or stopped early
        add_pixel_means(t.values[0], kPixels, t.n, t.most, w.pixels);
        ++at_pixels;
        if (t.spread.empty()) continue;
        add_pixel_means(t.spread[0], kSpreadPixels, kPilotSpreadSamples, kPilotSpreadSamples, w.spread);
        ++at_spread;
    }
    for (double& x : w.pixels) x = relative_error_weight(at_pixels > 0 ? x / at_pixels : 0.0);
    for (double& x : w.spread) x = relative_error_weight(at_spread > 0 ? x / at_spread : 0.0);
    return w;
}

// Every candidate's figures in `out` (those traced so far), from their samples and the weights their
// pixel means give together; f: the share of the image the pilot pixels stand for.
void add_figures(const std::vector<TracedSamples>& traced, double f, std::vector<GatherMeasurement>& out) {
    const RelativeWeights w = relative_weights(traced);
    for (size_t c = 0; c < out.size(); ++c) {
        const TracedSamples& t = traced[c];
        GatherMeasurement& g = out[c];
        if (g.dropped) continue;
        const double v = summed_pixel_variance(t.values[0], t.n, t.most, w.pixels);
        g.v_camera = v / kPixels;
        if (!t.spread.empty()) g.v_camera = (v + summed_spread_variance(t.spread[0], w.spread)) / (kPixels + kSpreadPixels);
        add_sample_statistics(t.values[0], t.n, t.most, w.pixels, g);
        if (t.halves_too) add_map_noise(t.values, t.spread, t.n, w.pixels, w.spread, g);
        // Averages over the image: the pixels that can vary, times their share (the rest add 0). The
        // mean stays theirs (the background's radiance need not be 0): it only compares candidates.
        for (double* x : {&g.v_camera, &g.v_map_half, &g.v_map_half_se, &g.bias2, &g.bias_mean, &g.bias_se}) *x *= f;
    }
}

// What the candidates' measurements share (measure_gathers), and the samples they traced.
struct PilotRun {
    PilotRun(const Camera& c, const PhotonMap& m, MapNoisePilotHooks& h) : camera(c), map(m), hooks(h) {}
    const Camera& camera;
    const PhotonMap& map;
    MapNoisePilotHooks& hooks;
    uint64_t seed = 0, stream = 0;
    PilotBudget budget;
    double image_pixels = 0.0;
    PilotPixels where;
    CountedOperations background;   // a background pixel's sample (background_work)
    double work_before = 0.0;       // work counted before the first candidate
    std::vector<PhotonMap> halves;  // built once a candidate's samples used the map
    std::vector<TracedSamples> traced;
    std::vector<GatherMeasurement> out;
    bool one_fits = false;          // an earlier candidate's one-sample pass fits the cap (render/plan/pilot_budget.h)

    // One camera sample's luminance, jittered within pixel (px, py).
    double sample(int px, int py, Rng& rng) const {
        const double jx = rng.uniform(), jy = rng.uniform();
        return luminance_of(hooks.trace(camera.generate_ray(px + jx, py + jy), rng));
    }

    // Samples s0 .. s1 - 1 of every pilot pixel for candidate c with its map m. The same numbers for
    // every map and candidate: the differences are the maps'. Samples past kPilotSamples (a
    // candidate without a map) draw from streams of their own.
    void trace(size_t c, size_t m, int s0, int s1) {
        TracedSamples& t = traced[c];
        tbb::parallel_for(0, kPixels, [&](int j) {
            const auto [px, py] = where.pixels[size_t(j)];
            for (int s = s0; s < s1; ++s) {
                Rng rng = s < kPilotSamples
                              ? Rng(seed, stream * uint64_t(kPixels * kPilotSamples) + uint64_t(j * kPilotSamples + s))
                              : Rng(mix64(seed ^ kLongPilotSalt), stream * uint64_t(kPixels * kNoMapPilotSamples) + at(j, s, t.most));
                t.values[m][at(j, s, t.most)] = sample(px, py, rng);
            }
        });
    }

    // g's operations per sample over the image after n samples per pilot pixel since `before`.
    void set_cost(GatherMeasurement& g, const CountedOperations& before, int n) const {
        g.per_sample = mixed(where.seen_fraction, per_sample(before, hooks.counts(), double(kPixels * n)), background);
        g.sample_cost = hooks.work(g.per_sample);
    }
};

// The candidate without a map (c) traced to n samples per pilot pixel in stages of kNoMapStopFirstStage,
// doubling, each tested by hooks.stop on every candidate's figures so far (render/plan/no_map_stop.h).
// Returns the samples traced; g holds the last test's figures and whether it stopped.
int trace_without_map(PilotRun& run, size_t c, int n, const CountedOperations& before, GatherMeasurement& g) {
    int traced = 1;   // the probe
    for (int stage = run.hooks.stop ? std::min(kNoMapStopFirstStage, n) : n;; stage = std::min(2 * stage, n)) {
        run.trace(c, 0, traced, stage);
        traced = stage;
        if (stage >= n) return n;
        std::vector<GatherMeasurement> so_far = run.out;
        GatherMeasurement& partial = so_far.emplace_back(g);
        run.set_cost(partial, before, stage);
        partial.samples = stage;
        run.traced[c].n = stage;
        add_figures(run.traced, run.where.seen_fraction, so_far);
        run.traced[c].n = 0;
        const bool stop = run.hooks.stop(so_far);
        g.stop_low_score = so_far.back().stop_low_score;
        g.stop_best_map_score = so_far.back().stop_best_map_score;
        if (stop) {
            g.stopped_early = true;
            return stage;
        }
    }
}

// Candidate c's probe, samples with the full map and (where it used the map) its halves, and the
// spread grid's; appended to run.out (its figures come later: add_figures).
void measure_candidate(PilotRun& run, size_t c, const PilotCandidate& candidate) {
    MapNoisePilotHooks& hooks = run.hooks;
    const bool may_use_halves = candidate.uses_map;
    TracedSamples& t = run.traced[c];
    t.most = may_use_halves ? kPilotSamples : kNoMapPilotSamples;
    t.values.assign(may_use_halves ? 3 : 1, std::vector<double>(size_t(kPixels) * size_t(t.most)));
    GatherMeasurement g;
    g.name = candidate.name;
    g.uses_map = candidate.uses_map;
    // The probe: one sample per pixel with the full map gives the counted cost per sample.
    hooks.use(int(c), &run.map);
    const CountedOperations before = hooks.counts();
    run.trace(c, 0, 0, 1);
    const CountedOperations probe = per_sample(before, hooks.counts(), double(kPixels));
    const double probe_cost = hooks.work(probe);   // at the pilot's pixels: what its samples cost
    const double image_probe_cost = hooks.work(mixed(run.where.seen_fraction, probe, run.background));   // over the image
    const bool over_cap = run.image_pixels * image_probe_cost > run.budget.max_pass_cost;
    if (run.budget.per_candidate > 0.0 && run.one_fits && over_cap) {
        g.dropped = true;
        g.samples = 1;
        g.per_sample = mixed(run.where.seen_fraction, probe, run.background);
        g.sample_cost = image_probe_cost;
        g.max_weight = hooks.counts().march_weight_max;
        run.out.push_back(g);
        return;
    }
    run.one_fits = run.one_fits || !over_cap;
    // Share the budget as if the halves were traced (render/plan/pilot_budget.h), whether or not they are.
    int n = candidate_samples(run.budget, probe_cost, may_use_halves ? 3 : 1, may_use_halves, hooks.work(before) - run.work_before);
    if (may_use_halves) run.trace(c, 0, 1, n);
    else n = trace_without_map(run, c, n, before, g);
    run.set_cost(g, before, n);
    std::vector<const PhotonMap*> maps = {&run.map};
    t.halves_too = may_use_halves && g.per_sample.map_used > 0.0;
    if (t.halves_too) {
        if (run.halves.empty()) run.halves = split_by_walk_group(run.map, 2);
        maps.push_back(&run.halves[0]);
        maps.push_back(&run.halves[1]);
    }
    for (size_t m = 1; m < maps.size(); ++m) {
        hooks.use(int(c), maps[m]);
        run.trace(c, m, 0, n);
    }
    g.samples = n;
    t.stopped = g.stopped_early;
    g.max_weight = hooks.counts().march_weight_max;   // over this candidate's traces (and the earlier ones')
    g.v_map_quarter = -1.0;
    t.n = n;
    // The spread grid's samples with each map (the full map, then the halves where traced).
    if (may_use_halves)
        t.spread = spread_samples(run.where, maps, int(c), hooks, run.seed, run.stream,
                                  [&run](int px, int py, Rng& rng) { return run.sample(px, py, rng); });
    run.out.push_back(g);
}

}  // namespace

std::vector<GatherMeasurement> measure_gathers(const Camera& camera, const PhotonMap& map,
                                               const std::vector<PilotCandidate>& candidates,
                                               MapNoisePilotHooks& hooks, uint64_t seed, uint64_t stream,
                                               const PilotBudget& budget, double image_pixels) {
    // The halves are built once a candidate's full-map samples used the map: where none did (every
    // ball wider than max_radius_mfp, the dense boxes) a half map's balls, wider still, are not used
    // either, V_map and bias^2 are exactly 0, and the split (two kd-trees: most of a 1 s pilot in the
    // dense boxes at 0.8 M stored photons) is skipped.
    PilotRun run(camera, map, hooks);
    run.seed = seed;
    run.stream = stream;
    run.budget = budget;
    run.image_pixels = image_pixels;
    run.traced.resize(candidates.size());
    // The pixels that can vary (render/plan/pilot_pixels.h): the figures are theirs times their share.
    run.where = choose_pilot_pixels(camera.width(), camera.height(), kPilotSide, kPilotSpreadSide, [&](int x, int y) {
        return !hooks.sees || hooks.sees(camera.generate_ray(x + 0.5, y + 0.5));
    });
    run.background = background_work(run.where, map, hooks, seed, stream,
                                      [&run](int px, int py, Rng& rng) { return run.sample(px, py, rng); });
    run.work_before = hooks.work(hooks.counts());   // the earlier candidates' work: what this pilot spent
    for (size_t c = 0; c < candidates.size(); ++c) measure_candidate(run, c, candidates[c]);
    // The figures, once every candidate's samples give the pixels' weights in the relative error.
    add_figures(run.traced, run.where.seen_fraction, run.out);
    return run.out;
}

}  // namespace vpm
