#pragma once
// Photons of random walks for the query benchmarks (bench_photon_map, bench_walk_query): walks of
// albedo 0.5 (mean 2 photons, an Exp(1) flight apart, isotropic) started uniformly in a cube of side
// `side` mean free paths, until `count` photons are stored; each photon carries its walk's label.
#include <cmath>
#include <vector>

#include "core/sampling/rng.h"
#include "core/sampling/sampling.h"
#include "photon/map/photon_map.h"

namespace vpm::bench {

inline std::vector<PhotonInput> walk_photons(Rng& rng, size_t count, double side) {
    std::vector<PhotonInput> in;
    for (uint64_t w = 0; in.size() < count; ++w) {
        Vec3 x(side * rng.uniform(), side * rng.uniform(), side * rng.uniform());
        do {
            PhotonInput p;
            p.position = x;
            p.direction = sample_uniform_sphere(rng.uniform(), rng.uniform());
            p.power = Rgb::Constant(1e-6);
            p.walk = w;
            in.push_back(p);
            x += -std::log(1.0 - rng.uniform()) * sample_uniform_sphere(rng.uniform(), rng.uniform());
        } while (rng.uniform() < 0.5);
    }
    return in;
}

}  // namespace vpm::bench
