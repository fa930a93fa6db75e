#pragma once
// Pilot hooks (render/plan/map_noise_pilot.h) for a plan's candidates without a renderer: the gathers
// (with a map) return uniform samples at 40 work units each; candidate `no_map_index` (no map, the
// path tracer's) returns `no_map(rng)` at 1 unit. Every sample counts as one used query.
#include <atomic>
#include <cstdint>
#include <functional>

#include "core/sampling/rng.h"
#include "render/plan/map_noise_pilot.h"

namespace vpm::test {

struct FakeMapPilot {
    explicit FakeMapPilot(int no_map_index) : no_map_index(no_map_index) {}
    int no_map_index;
    std::atomic<int64_t> work{0};
    int current = 0;
    std::function<double(Rng&)> no_map;
    MapNoisePilotHooks hooks() {
        MapNoisePilotHooks h;
        h.use = [this](int c, const PhotonMap*) { current = c; };
        h.trace = [this](const Ray&, Rng& rng) {
            const bool path = current == no_map_index;
            work += path ? 1 : 40;
            return Rgb::Constant(path ? no_map(rng) : rng.uniform());
        };
        h.counts = [this] {
            CountedOperations c;
            c.rays = double(work.load());
            c.queries = c.map_used = c.rays;
            return c;
        };
        h.work = [](const CountedOperations& c) { return c.rays; };
        return h;
    }
};

}  // namespace vpm::test
