#pragma once
// The photon pass: lights emit N photons, which travel by delta tracking through the scene's
// media, are stored at real collisions, scatter by HG with probability albedo (Russian roulette
// on the RGB albedo with weight albedo / q, so the expected power is exact per channel), bounce
// off Lambertian surfaces the same way, leave the scene, or hit the path-length cap.
//
// Storage convention (DESIGN.md section 2): photons are stored at every real collision, with the
// power arriving there. With `store_direct` false (single scattering by NEE) a photon is stored
// only once its path has scattered at least once (off a medium or a surface), so the map holds
// exactly the light that NEE does not.
//
// Energy is accounted per run: emitted = absorbed + escaped + truncated, where "absorbed" is the
// power removed at each event (power in minus power out), so the balance telescopes exactly and
// a photon that vanishes unaccounted shows up as an imbalance.
#include <cstdint>
#include <vector>

#include "photon/photon.h"
#include "scene/scene.h"

namespace vpm {

struct PhotonTraceSettings {
    uint64_t count = 100000;
    uint64_t seed = 1;
    uint64_t stream_offset = 0;   // independent photon maps with the same seed
    bool store_direct = true;
    int max_bounces = 1000;       // collisions + surface bounces per path before truncation
    bool progress = true;
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
    EnergyBalance energy;
    uint64_t paths = 0;
    uint64_t collisions = 0;            // real medium collisions, stored or not
    uint64_t truncated_paths = 0;
    double seconds = 0.0;
};

PhotonTraceResult trace_photons(const Scene& scene, const PhotonTraceSettings& settings);

}  // namespace vpm
