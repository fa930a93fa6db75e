#include "photon/photon_tracer.h"

#include <algorithm>
#include <atomic>

#include <tbb/parallel_for.h>

#include "core/henyey_greenstein.h"
#include "core/progress.h"
#include "core/sampling.h"
#include "transport/walk_steps.h"

namespace vpm {

namespace {

// Photons per independent batch. Batches are the unit of determinism: each has its own Rng
// stream and output slot, and results are concatenated in batch order.
constexpr uint64_t kBatchSize = 4096;

// Picks a light with probability proportional to its luminance power.
struct LightPicker {
    std::vector<double> cdf;
    explicit LightPicker(const Scene& scene) {
        double sum = 0.0;
        for (const auto& l : scene.lights) {
            sum += std::max(0.0, luminance(l->power()));
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
    EnergyBalance energy;
    uint64_t collisions = 0, truncated_paths = 0, surface_hits = 0;
};

void trace_batch(const Scene& scene, const PhotonTraceSettings& s, const LightPicker& picker, uint64_t batch,
                 BatchOutput& out) {
    Rng rng(s.seed ^ 0x70686f746f6eULL, batch + s.stream_offset * ((s.count + kBatchSize - 1) / kBatchSize));
    const uint64_t begin = batch * kBatchSize, end = std::min(s.count, begin + kBatchSize);
    const double inv_n = 1.0 / double(s.count);
    for (uint64_t i = begin; i < end; ++i) {
        double light_pdf = 1.0;
        const Light& light = *scene.lights[picker.pick(rng.uniform(), light_pdf)];
        EmissionSample e = light.sample_emission(rng);
        Rgb power = e.power * (inv_n / light_pdf);
        out.energy.emitted += power;
        Ray ray = e.ray;
        bool scattered = false;
        int bounces = 0;
        for (;;) {
            if (bounces >= s.max_bounces) {
                out.energy.truncated += power;
                ++out.truncated_paths;
                break;
            }
            const PathVertex v = next_vertex(scene, ray, rng);
            const MediumEvent& event = v.medium;
            const SurfaceHit& hit = v.hit;
            if (v.escaped()) {
                out.energy.escaped += power;
                break;
            }
            ++bounces;
            const Rgb power_in = power;
            bool alive;
            if (event) {
                const Vec3 x = ray.at(event.t);
                ++out.collisions;
                if (s.store_direct || scattered) out.photons.push_back(PhotonInput{x, ray.dir, power});
                alive = roulette(power, event.medium->albedo(), rng);
                if (alive) {
                    const double u1 = rng.uniform(), u2 = rng.uniform();
                    ray = Ray{x, hg_sample(ray.dir, event.medium->g(), u1, u2)};
                }
            } else {
                ++out.surface_hits;
                if (s.store_surface && (s.store_direct || scattered) && (hit.reflectance > 0.0).any())
                    out.surface_photons.push_back(PhotonInput{hit.position, ray.dir, power});
                alive = roulette(power, hit.reflectance, rng);
                if (alive) ray = diffuse_bounce(hit, rng);
            }
            if (!alive) power = Rgb::Zero();
            out.energy.absorbed += power_in - power;
            if (!alive) break;
            scattered = true;
        }
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
    PhotonTraceResult result;
    const Timer timer;
    const LightPicker picker(scene);
    const uint64_t batches = (s.count + kBatchSize - 1) / kBatchSize;
    std::vector<BatchOutput> outputs(batches);
    Progress progress("photons", batches, s.progress);
    tbb::parallel_for(uint64_t(0), batches, [&](uint64_t b) {
        trace_batch(scene, s, picker, b, outputs[b]);
        progress.advance();
    });
    progress.done();
    size_t total = 0, total_surface = 0;
    for (const auto& o : outputs) {
        total += o.photons.size();
        total_surface += o.surface_photons.size();
    }
    result.photons.reserve(total);
    result.surface_photons.reserve(total_surface);
    for (auto& o : outputs) {   // fixed order: deterministic sums and photon order
        result.photons.insert(result.photons.end(), o.photons.begin(), o.photons.end());
        std::vector<PhotonInput>().swap(o.photons);
        result.surface_photons.insert(result.surface_photons.end(), o.surface_photons.begin(), o.surface_photons.end());
        std::vector<PhotonInput>().swap(o.surface_photons);
        result.surface_hits += o.surface_hits;
        result.energy.emitted += o.energy.emitted;
        result.energy.absorbed += o.energy.absorbed;
        result.energy.escaped += o.energy.escaped;
        result.energy.truncated += o.energy.truncated;
        result.collisions += o.collisions;
        result.truncated_paths += o.truncated_paths;
    }
    result.paths = s.count;
    result.seconds = timer.seconds();
    return result;
}

}  // namespace vpm
