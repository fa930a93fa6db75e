#include "photon/trace/photon_tracer.h"

#include <algorithm>
#include <atomic>

#include <tbb/parallel_for.h>
#include <tbb/task_group.h>

#include "core/error.h"
#include "core/henyey_greenstein.h"
#include "core/progress.h"
#include "core/sampling/sampling.h"
#include "photon/trace/forced_collision.h"
#include "photon/trace/store_thinning.h"
#include "transport/specular_step.h"
#include "transport/walk_steps.h"

namespace vpm {

namespace {

// Photons per independent batch. Batches are the unit of determinism: each has its own Rng
// stream and output slot, and results are concatenated in batch order.
constexpr uint64_t kBatchSize = 4096;
constexpr uint64_t kPilotBatches = 16;    // the first chunk: 65536 photons
constexpr uint64_t kAutoBatches = 1;      // store_probability "auto": its counts come from batch 0 alone
constexpr uint64_t kChunkBatches = 256;   // then ~1M photons per chunk
constexpr uint64_t kPhotonSalt = 0x70686f746f6e73ULL;   // photon sample sets apart from camera sets

// Picks a light with probability proportional to its weight: settings.light_weights when given
// (photon/trace/photon_allocation.h), else its luminance power. A photon's power is divided by the
// pick probability, so any weights that are positive wherever a light has power are unbiased.
struct LightPicker {
    std::vector<double> cdf;
    LightPicker(const Scene& scene, const std::vector<double>& weights, int single_light) {
        if (single_light >= 0) {
            if (size_t(single_light) >= scene.lights.size())
                throw Error("photon tracer: single_light " + std::to_string(single_light) + " out of range");
            for (size_t i = 0; i < scene.lights.size(); ++i) cdf.push_back(int(i) >= single_light ? 1.0 : 0.0);
            return;
        }
        if (!weights.empty() && weights.size() != scene.lights.size())
            throw Error("photon tracer: " + std::to_string(weights.size()) + " light weights for " +
                        std::to_string(scene.lights.size()) + " lights");
        double sum = 0.0;
        for (size_t i = 0; i < scene.lights.size(); ++i) {
            const double power = std::max(0.0, luminance(scene.lights[i]->power()));
            double w = power;
            if (!weights.empty()) {
                w = weights[i];
                if (!(w >= 0.0) || !std::isfinite(w) || (power > 0.0 && w == 0.0))
                    throw Error("photon tracer: light " + std::to_string(i) + " has weight " + std::to_string(w) +
                                " (allowed: finite, > 0 where the light has power)");
            }
            sum += w;
            cdf.push_back(sum);
        }
        for (double& c : cdf) c = sum > 0 ? c / sum : 1.0;
    }
    size_t pick(double u, double& pdf) const {
        const size_t i = size_t(std::upper_bound(cdf.begin(), cdf.end(), u) - cdf.begin());
        const size_t idx = std::min(i, cdf.size() - 1);
        pdf = cdf[idx] - (idx ? cdf[idx - 1] : 0.0);
        return idx;
    }
};

// Survive with probability q = max channel of `factor`; the surviving power is power * factor / q.
// Returns false when the photon is terminated.
bool roulette(Rgb& power, const Rgb& factor, Rng& rng) {
    const double q = factor.maxCoeff();
    if (q <= 0.0 || rng.uniform() >= q) return false;
    power *= factor / q;
    return true;
}

struct BatchOutput {
    std::vector<PhotonInput> photons, surface_photons;
    std::vector<RegionMask> photon_regions, surface_photon_regions, beam_regions;
    std::vector<PhotonBeam> beams;
    EnergyBalance energy;
    uint64_t collisions = 0, truncated_paths = 0, surface_hits = 0, light_hits = 0, storing_walks = 0;
    std::vector<LightPhotonStats> per_light;
};

// The flight's part inside the media's box as a beam (photons.gather = "photon_beams"), with the
// photon's region where the scene has glass (a free flight crosses no glass).
void record_beam(const Bounds3& media_bounds, const Ray& ray, double flight, const Rgb& power, uint64_t path,
                 const RegionMask* region, BatchOutput& out) {
    double t0, t1;
    if (!media_bounds.intersect(ray, flight, t0, t1) || !(t1 > t0) || !std::isfinite(t1)) return;
    out.beams.push_back(PhotonBeam{ray.at(t0), ray.dir, t1 - t0, power, path});
    if (region) out.beam_regions.push_back(*region);
}

// A forced collision's step: the share exp(-tau) passes the medium (out of the scene, or into a black
// surface) and leaves the power; below the weight window's floor the rest plays roulette up to it.
// false: the photon ended there.
bool forced_passage(double transmittance, bool on_surface, double window, Rgb& power, Rng& rng, EnergyBalance& energy) {
    const Rgb passed = power * transmittance;
    (on_surface ? energy.absorbed : energy.escaped) += passed;
    power -= passed;
    if (!(power.maxCoeff() < window)) return true;   // at or above the floor (or NaN): unchanged
    const double keep = power.maxCoeff() / window;
    if (!(keep > 0.0) || rng.uniform() >= keep) {
        energy.absorbed += power;
        return false;
    }
    energy.absorbed += power - power / keep;   // negative: the survivor carries the rest
    power /= keep;
    return true;
}

// q: the volume storage probability for this batch.
void trace_batch(const Scene& scene, const PhotonTraceSettings& s, const LightPicker& picker, uint64_t batch, double q,
                 BatchOutput& out) {
    Rng rng(s.seed ^ 0x70686f746f6eULL, batch + s.stream_offset * ((s.count + kBatchSize - 1) / kBatchSize));
    const uint64_t begin = batch * kBatchSize, end = std::min(s.count, begin + kBatchSize);
    const bool whole_pass = s.sampler == SamplerKind::sobol;   // one Sobol' set over the pass's photons
    PathSampler sampler(s.sampler, sampler_key(s.seed, s.stream_offset, whole_pass ? 0 : batch + 1, kPhotonSalt),
                        whole_pass ? s.count : end - begin);
    if (s.sampler != SamplerKind::independent) rng.draw_from(&sampler);
    const double inv_n = 1.0 / double(s.count);
    out.per_light.assign(scene.lights.size(), LightPhotonStats{});
    const bool forced_ok = s.forced_collisions && forced_collisions_possible(scene);
    OpticalDepthProfile profile;
    Bounds3 media_bounds;   // beams are clipped to it
    for (const auto& m : scene.media) media_bounds.extend(m->bounds());
    const Surfaces* surfaces = scene.surfaces.get();
    const bool regions = surfaces && !surfaces->dielectric_shapes().empty();
    for (uint64_t i = begin; i < end; ++i) {
        sampler.start_sample(whole_pass ? i : i - begin);
        double light_pdf = 1.0;
        const size_t light_index = picker.pick(rng.uniform(), light_pdf);
        const Light& light = *scene.lights[light_index];
        LightPhotonStats& light_stats = out.per_light[light_index];
        const size_t stored_before = out.photons.size() + out.surface_photons.size();
        const size_t volume_before = out.photons.size();
        ++light_stats.emitted;
        EmissionSample e = light.sample_emission(rng);
        Rgb power = e.power * (inv_n / light_pdf);
        out.energy.emitted += power;
        Ray ray = e.ray;
        RegionMask region = regions ? region_at(surfaces, ray.origin) : 0;
        const double window = kForcedWindow * power.maxCoeff();   // forced steps: the weight window's floor
        bool scattered = false;
        int bounces = 0;
        // Every photon and beam of this walk: its label is the path index i, its group i mod kWalkGroups (photon.h).
        const uint8_t group = uint8_t(i % kWalkGroups);
        for (;;) {
            if (bounces >= s.max_bounces) {
                out.energy.truncated += power;
                ++out.truncated_paths;
                break;
            }
            const ForcedStep forced = forced_ok ? forced_step(scene, ray, rng, profile)
                                                : ForcedStep{next_vertex(scene, ray, rng), 1.0, false};
            const PathVertex& v = forced.vertex;
            const MediumEvent& event = v.medium;
            const SurfaceHit& hit = v.hit;
            if (s.store_beams && !forced.forced && (s.store_direct || scattered))
                record_beam(media_bounds, ray, event ? event.t : v.on_surface ? hit.t : kInfinity, power, i,
                            regions ? &region : nullptr, out);
            if (v.escaped()) {
                out.energy.escaped += power;
                break;
            }
            if (bounces == 0) ++light_stats.landed;
            ++bounces;
            if (event && forced.forced && !forced_passage(forced.transmittance, v.on_surface, window, power, rng, out.energy))
                break;
            const Rgb power_in = power;
            bool alive;
            if (event) {
                const Vec3 x = ray.at(event.t);
                ++out.collisions;
                if (s.store_volume && (s.store_direct || scattered)) {
                    const size_t before = out.photons.size();
                    if (q >= 1.0) out.photons.push_back(PhotonInput{x, ray.dir, power, group, i});
                    else if (rng.uniform() < q)
                        out.photons.push_back(PhotonInput{x, ray.dir, power / q, group, i});
                    if (regions && out.photons.size() > before) out.photon_regions.push_back(region);
                }
                alive = roulette(power, event.medium->albedo(), rng);
                if (alive) {
                    const double u1 = rng.uniform(), u2 = rng.uniform();
                    ray = Ray{x, hg_sample(ray.dir, event.medium->g(), u1, u2)};
                }
            } else {
                ++out.surface_hits;
                if (hit.emitter) ++out.light_hits;
                if (hit.specular) {   // mirror or glass: on without storing (a caustic photon from here on)
                    alive = photon_specular_step(hit, ray, power, rng);
                    if (alive) region = region_after_specular(region, hit, ray.dir);
                } else {
                    if (s.store_surface && (s.store_direct || scattered) && (hit.reflectance > 0.0).any()) {
                        out.surface_photons.push_back(PhotonInput{hit.position, ray.dir, power, group, i});
                        if (regions) out.surface_photon_regions.push_back(region);
                    }
                    alive = roulette(power, hit.reflectance, rng);
                    if (alive) ray = diffuse_bounce(hit, rng);
                }
            }
            if (!alive) power = Rgb::Zero();
            out.energy.absorbed += power_in - power;
            if (!alive) break;
            scattered = true;
        }
        light_stats.stored += out.photons.size() + out.surface_photons.size() - stored_before;
        if (out.photons.size() > volume_before) ++out.storing_walks;
    }
}

}  // namespace

double EnergyBalance::relative_imbalance() const {
    const Rgb residual = emitted - absorbed - escaped - truncated;
    double worst = 0.0;
    for (int c = 0; c < 3; ++c)
        if (emitted[c] > 0) worst = std::max(worst, std::abs(residual[c]) / emitted[c]);
    return worst;
}

PhotonTraceResult trace_photons(const Scene& scene, const PhotonTraceSettings& s) {
    scene.prepare_photon_emission();   // the lights' guides, once per scene (scene/emission_guides.h)
    PhotonTraceResult result;
    const Timer timer;
    const LightPicker picker(scene, s.light_weights, s.single_light);
    const uint64_t batches = (s.count + kBatchSize - 1) / kBatchSize;
    Progress progress("photons", batches, s.progress);
    // Chunks of batches, merged in batch order (the same photons and sums as one parallel loop over
    // all batches): memory for per-batch outputs stays bounded whatever the count, and after each
    // chunk the caller sees the running totals (pilot projection, budget, progress lines).
    PhotonTraceProgress totals;
    totals.total = s.count;
    // "auto": batch 0 stores all, its counts set q for the rest (same on any thread count).
    double q = s.store_auto ? 1.0 : s.store_probability;
    for (uint64_t first = 0; first < batches;) {
        // "auto" splits the pilot chunk after batch 0, whose walks set q for every later batch.
        const uint64_t head = s.store_auto && first == 0 ? kAutoBatches : kPilotBatches;
        const uint64_t n = std::min(batches - first, first < kPilotBatches ? head - first : kChunkBatches);
        std::vector<BatchOutput> outputs(n);
        tbb::parallel_for(uint64_t(0), n, [&](uint64_t b) {
            // A cancelled task group (the Python module's Ctrl-C) skips its remaining batches at once
            // (one task may hold many); the caller discards the result.
            if (tbb::is_current_task_group_canceling()) return;
            trace_batch(scene, s, picker, first + b, q, outputs[b]);
            progress.advance();
        });
        for (auto& o : outputs) {   // fixed order: deterministic sums and photon order
            result.photons.insert(result.photons.end(), o.photons.begin(), o.photons.end());
            std::vector<PhotonInput>().swap(o.photons);
            result.surface_photons.insert(result.surface_photons.end(), o.surface_photons.begin(),
                                          o.surface_photons.end());
            std::vector<PhotonInput>().swap(o.surface_photons);
            result.photon_regions.insert(result.photon_regions.end(), o.photon_regions.begin(), o.photon_regions.end());
            result.surface_photon_regions.insert(result.surface_photon_regions.end(), o.surface_photon_regions.begin(),
                                                 o.surface_photon_regions.end());
            result.beams.insert(result.beams.end(), o.beams.begin(), o.beams.end());
            std::vector<PhotonBeam>().swap(o.beams);
            result.beam_regions.insert(result.beam_regions.end(), o.beam_regions.begin(), o.beam_regions.end());
            result.surface_hits += o.surface_hits;
            result.light_hits += o.light_hits;
            result.energy.emitted += o.energy.emitted;
            result.energy.absorbed += o.energy.absorbed;
            result.energy.escaped += o.energy.escaped;
            result.energy.truncated += o.energy.truncated;
            result.collisions += o.collisions;
            result.truncated_paths += o.truncated_paths;
            result.storing_walks += o.storing_walks;
            if (result.per_light.empty()) result.per_light.assign(scene.lights.size(), LightPhotonStats{});
            for (size_t l = 0; l < o.per_light.size(); ++l) {
                result.per_light[l].emitted += o.per_light[l].emitted;
                result.per_light[l].landed += o.per_light[l].landed;
                result.per_light[l].stored += o.per_light[l].stored;
            }
        }
        first += n;
        totals.emitted = std::min(s.count, first * kBatchSize);
        totals.stored = result.photons.size();
        totals.surface_stored = result.surface_photons.size();
        totals.beams = result.beams.size();
        totals.seconds = timer.seconds();
        if (s.store_auto && first == kAutoBatches) q = auto_store_probability(result.photons.size(), result.storing_walks);
        if (s.store_auto && totals.emitted > 0) {   // the rest at q, against the mean probability so far
            const double pilot = double(std::min(s.count, kAutoBatches * kBatchSize));
            totals.later_store_fraction = q * double(totals.emitted) / (pilot + q * (double(totals.emitted) - pilot));
        }
        if (s.on_chunk) s.on_chunk(totals);
        if (first == kPilotBatches && first < batches && totals.emitted > 0) {
            // Reserve what the pilot projects (+10%, thinned by "auto"'s q), so the record vectors
            // are not reallocated (a reallocation briefly holds both copies).
            const double scale = 1.1 * double(s.count) / double(totals.emitted) * (s.store_auto ? q : 1.0);
            result.photons.reserve(size_t(double(totals.stored) * scale) + kBatchSize);
            if (s.store_surface) result.surface_photons.reserve(size_t(double(totals.surface_stored) * scale) + kBatchSize);
            if (s.store_beams)   // every free flight of a storing walk, unthinned
                result.beams.reserve(size_t(1.1 * double(totals.beams) * double(s.count) / double(totals.emitted)) + kBatchSize);
        }
    }
    progress.done();
    result.paths = s.count;
    result.seconds = timer.seconds();
    result.store_probability = q;
    return result;
}

}  // namespace vpm
