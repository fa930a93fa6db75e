#pragma once
// Pilot hooks (render/plan/map_noise_pilot.h) around a synthetic trace: no gather to switch, and every
// sample counted as one used query and one ray of one work unit, so that the pilot's figures are
// the trace's alone.
#include <functional>

#include "render/plan/map_noise_pilot.h"

namespace vpm::test {

inline MapNoisePilotHooks synthetic_pilot_hooks(std::function<Rgb(const Ray&, Rng&)> trace) {
    MapNoisePilotHooks hooks;
    hooks.use = [](int, const PhotonMap*) {};
    hooks.trace = std::move(trace);
    hooks.counts = [] {
        CountedOperations c;
        c.queries = c.map_used = c.rays = 1.0;
        return c;
    };
    hooks.work = [](const CountedOperations& c) { return c.rays; };
    return hooks;
}

}  // namespace vpm::test
