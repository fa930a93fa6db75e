#pragma once
// The photon pass: lights emit N photons, which travel by delta tracking through the scene's
// media, are stored at real collisions, scatter by HG with probability albedo (Russian roulette
// on the RGB albedo with weight albedo / q, so the expected power is exact per channel), bounce
// off Lambertian surfaces the same way, leave the scene, or hit the path-length cap.
//
// Storage convention (docs/design.md section 2): photons are stored at every real collision, with the
// power arriving there. With `store_direct` false (single scattering by NEE) a photon is stored
// only once its path has scattered at least once (off a medium or a surface), so the map holds
// exactly the light that NEE does not.
//
// Surface photons (`store_surface`): a photon hitting a Lambertian surface (reflectance not zero)
// is stored in `surface_photons` with the power arriving there and its incoming travel direction,
// before Russian roulette on the reflectance decides whether it bounces on. The same rule applies:
// with `store_direct` false only photons that scattered before (off a medium or a surface) are
// stored, since NEE gives surfaces their direct light; with `store_direct` true every hit is
// stored. Black surfaces (reflectance 0) store nothing: they reflect no light. Storing changes no
// power, so the energy balance is the same with or without it.
//
// Mirrors and glass (transport/specular_step.h): a photon goes on along the material's sampled
// direction, its power times the material's weight (Russian roulette on it), and stores nothing
// there. Every photon that has met one counts as scattered: NEE cannot reach through a specular
// interface, so with `store_direct` false such photons (caustic photons) are stored at their next
// medium collision or diffuse hit, after any number of specular events.
//
// Regions (scene/dielectric_regions.h): in a scene with closed dielectric shapes every photon's walk
// carries the set of glass shapes containing it (region_at where the light emits it, toggled at each
// refraction), and every stored photon records it in photon_regions / surface_photon_regions, so
// that an estimate counts only photons of its own region (photon/map/region_photon_maps.h).
//
// Energy is accounted per run: emitted = absorbed + escaped + truncated, where "absorbed" is the
// power removed at each event (power in minus power out), so the balance telescopes exactly and
// a photon that vanishes unaccounted shows up as an imbalance.
#include <cstdint>
#include <functional>
#include <vector>

#include "core/sampling/sampler.h"
#include "photon/map/photon.h"
#include "photon/map/photon_beam.h"
#include "scene/dielectric_regions.h"
#include "scene/scene.h"

namespace vpm {

// Running totals handed to PhotonTraceSettings::on_chunk after each chunk of batches (in batch
// order, on the calling thread). The first chunk is small (16 batches, 65536 photons; with
// store_probability "auto" batch 0 alone, then the other 15): a pilot
// from which the caller can project the final counts and stop before the real work.
struct PhotonTraceProgress {
    uint64_t emitted = 0;          // photon paths traced so far
    uint64_t total = 0;            // photon paths to trace in all
    uint64_t stored = 0;           // volume photons stored so far
    uint64_t surface_stored = 0;   // surface photons stored so far
    uint64_t beams = 0;            // photon beams recorded so far (store_beams)
    double seconds = 0.0;          // since the pass started
    // Volume photons still to trace are stored at this fraction of the rate so far
    // (store_probability = "auto" after its first batch; 1 otherwise).
    double later_store_fraction = 1.0;
};

struct PhotonTraceSettings {
    uint64_t count = 100000;
    uint64_t seed = 1;
    uint64_t stream_offset = 0;   // independent photon maps with the same seed
    bool store_direct = true;
    bool store_surface = false;   // also fill surface_photons (Lambertian surface hits)
    // Each volume collision that would be stored is kept with this probability, its power divided
    // by it (unbiased thinning): fewer, less clustered photons per walk in dense, bright media.
    double store_probability = 1.0;
    // photons.store_probability = "auto" (photon/trace/store_thinning.h): store_probability is ignored;
    // batch 0 (4096 photons) stores every collision, the rest with the probability its counts give.
    bool store_auto = false;
    int max_bounces = 1000;       // collisions + surface bounces per path before truncation
    // Every segment in the medium collides, its power times 1 - exp(-tau) (photon/trace/forced_collision.h).
    bool forced_collisions = false;
    bool progress = true;
    // photons.sampler (core/sampling/sampler.h): independent keeps one PCG32 stream per batch; stratified
    // makes one sample set per batch (its photons), sobol one per pass (photon i reads point i).
    SamplerKind sampler = SamplerKind::independent;
    // Also record the photon beams (photon/map/photon_beam.h): every free flight that a stored photon
    // would have ended (the same store_direct rule), clipped to the media's bounds, at its full
    // power (no thinning: store_probability applies to the point photons). Not with
    // forced_collisions (a forced flight is not a free flight). Draws no random numbers.
    bool store_beams = false;
    // false: no volume photons are stored (the photon-beams gather needs only the beams).
    bool store_volume = true;
    // Called after each chunk; may throw (vpm::Error) to stop the pass, e.g. when the projected
    // map cannot fit in memory (photon/trace/photon_budget.h). Null: no callback.
    std::function<void(const PhotonTraceProgress&)> on_chunk;
    // Relative photon counts per light (one per scene light; photon/trace/photon_allocation.h). Empty:
    // proportional to luminance power. Photon power is divided by the pick probability, so any
    // weights > 0 wherever a light has power keep the map unbiased.
    std::vector<double> light_weights;
    // >= 0: every photon comes from this light, with its full power (pilot passes); the map then
    // holds that light's light only.
    int single_light = -1;
};

// Photons of one light: emitted, landed (reached a medium collision or a surface at all) and
// stored (volume + surface records).
struct LightPhotonStats {
    uint64_t emitted = 0, landed = 0, stored = 0;
};

struct EnergyBalance {
    Rgb emitted = Rgb::Zero();
    Rgb absorbed = Rgb::Zero();
    Rgb escaped = Rgb::Zero();
    Rgb truncated = Rgb::Zero();
    // max over channels of |emitted - absorbed - escaped - truncated| / emitted
    double relative_imbalance() const;
};

struct PhotonTraceResult {
    std::vector<PhotonInput> photons;   // in a fixed order for a given seed, any thread count
    std::vector<PhotonInput> surface_photons;   // store_surface: hits on Lambertian surfaces, same order rule
    std::vector<PhotonBeam> beams;              // store_beams: free flights in the media, same order rule
    // The region of each photon of `photons` / `surface_photons`, in their order; both empty in a
    // scene without closed dielectric shapes (every photon is in region 0 there).
    std::vector<RegionMask> photon_regions, surface_photon_regions;
    std::vector<RegionMask> beam_regions;   // the region of each beam of `beams`, the same rule
    EnergyBalance energy;
    uint64_t paths = 0;
    uint64_t collisions = 0;            // real medium collisions, stored or not
    uint64_t surface_hits = 0;          // surface hits, stored or not
    uint64_t light_hits = 0;            // of which on area lights (black: the photon is absorbed there)
    uint64_t truncated_paths = 0;
    std::vector<LightPhotonStats> per_light;   // one per scene light
    double seconds = 0.0;
    uint64_t storing_walks = 0;         // photon paths that stored at least one volume photon
    double store_probability = 1.0;     // the volume storage probability after batch 0
};

PhotonTraceResult trace_photons(const Scene& scene, const PhotonTraceSettings& settings);

}  // namespace vpm
