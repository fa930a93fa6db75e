#pragma once
// Samplers: where the uniform numbers of a camera path (render.sampler) or a photon path
// (photons.sampler) come from. A sampler makes a *set* of sample vectors (a pixel's samples in one
// pass, a photon batch, a pass's photons), each of unbounded dimension; a path reads its vector one
// dimension per call, in the order it draws (core/sampling/rng.h: an Rng bound to a PathSampler returns its
// next dimension), so walk code is the same for every sampler.
//
//   independent  today's PCG32 streams: the render loop and the photon tracer leave their Rng
//                unbound (bit for bit the images they always made); sample() here hashes (key,
//                index, dimension) for the study's point sets.
//   stratified   dimensions in consecutive pairs (0, 1), (2, 3), ...: each pair a jittered grid of
//                nx x ny >= n cells over the set's n vectors, vector i in cell pi(i) of a
//                per-pair hashed permutation (core/sampling/hashed_permutation.h), uniform inside it. Every
//                coordinate is uniform, pairs are independent of each other.
//   sobol        Joe & Kuo's Sobol' points (core/sampling/sobol.h), vector i = point i, each dimension with
//                its own Owen scramble (core/sampling/owen_scramble.h) seeded by (key, dimension): every
//                coordinate uniform (unbiased), the first 2^m vectors a (0, m, 2)-net in dimensions
//                0 and 1. Dimensions from kSobolDimensions on are padded: dimension d reads
//                dimension d mod kSobolDimensions at a hashed permutation of the index, which keeps
//                each one stratified in 1D and unrelated to the dimensions it shares a matrix with.
//
// Everything is a pure function of (key, index, dimension): deterministic and independent of the
// thread count. Keys differ per seed, pass and set (sampler_key), so passes draw independent
// scrambles and jitters.
#include <cstdint>

#include "core/sampling/rng.h"

namespace vpm {

enum class SamplerKind { independent, stratified, sobol };

// The key of one sample set: seed, stream (pass) and set (pixel, batch) mixed, `salt` apart camera
// from photon sets.
inline uint64_t sampler_key(uint64_t seed, uint64_t stream, uint64_t set, uint64_t salt) {
    return mix64(mix64(mix64(seed ^ salt) + stream) + set);
}

class PathSampler final : public DimensionSource {
public:
    // A set of `set_size` vectors (>= 1; stratified at most 2^31, sobol 2^32 - 1: else vpm::Error).
    PathSampler(SamplerKind kind, uint64_t key, uint64_t set_size);

    // The vector read next (index < set_size), from its dimension 0.
    void start_sample(uint64_t index) {
        index_ = index;
        dim_ = 0;
    }
    double next_dimension() override { return sample(index_, dim_++); }

    // Coordinate `dim` of vector `index`.
    double sample(uint64_t index, uint32_t dim) const;

    SamplerKind kind() const { return kind_; }
    uint64_t set_size() const { return n_; }
    uint32_t dimensions_read() const { return dim_; }

private:
    SamplerKind kind_;
    uint64_t key_;
    uint64_t n_;
    uint32_t nx_ = 1, ny_ = 1;   // stratified: the grid of every pair
    int depth_ = 0;              // sobol: scramble depth (2^depth >= n)
    uint64_t index_ = 0;
    uint32_t dim_ = 0;
};

}  // namespace vpm
