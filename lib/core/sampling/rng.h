#pragma once
// PCG32 (O'Neill 2014): small state, good statistics, and independent streams, which is what
// makes images independent of the thread count: every pixel / photon path gets its own stream
// derived from (seed, index) instead of sharing a generator between threads.
#include <cstdint>

namespace vpm {

// The dimensions of one sample vector, one per call (core/sampling/sampler.h: stratified and Sobol sets).
// An Rng bound to one (Rng::draw_from) returns its next dimension from uniform(), so walk code that
// takes an Rng draws from a sampler unchanged.
class DimensionSource {
public:
    virtual double next_dimension() = 0;

protected:
    ~DimensionSource() = default;
};

// SplitMix64 finaliser: turns structured inputs (seed, pixel index) into well-mixed 64-bit keys.
inline uint64_t mix64(uint64_t x) {
    x += 0x9e3779b97f4a7c15ULL;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
    return x ^ (x >> 31);
}

class Rng {
public:
    // seed selects the experiment, stream the independent sequence inside it (pixel, photon batch).
    explicit Rng(uint64_t seed = 0, uint64_t stream = 0) {
        inc_ = (mix64(stream ^ 0x5851f42d4c957f2dULL) << 1u) | 1u;
        state_ = 0;
        next_u32();
        // The stream also enters the state: PCG streams that share a state are related sequences.
        state_ += mix64(seed + mix64(stream));
        next_u32();
    }

    uint32_t next_u32() {
        const uint64_t old = state_;
        state_ = old * 6364136223846793005ULL + inc_;
        const uint32_t xorshifted = static_cast<uint32_t>(((old >> 18u) ^ old) >> 27u);
        const uint32_t rot = static_cast<uint32_t>(old >> 59u);
        return (xorshifted >> rot) | (xorshifted << ((~rot + 1u) & 31u));
    }

    // Uniform double in [0, 1) with 53 random bits; bound to a sampler, its next dimension.
    double uniform() {
        if (source_) return source_->next_dimension();
        const uint64_t hi = next_u32(), lo = next_u32();
        return static_cast<double>(((hi << 32) | lo) >> 11) * 0x1.0p-53;
    }

    // From now on uniform() returns the dimensions of `source` (not owned; nullptr: this stream
    // again). next_u32 and uniform_index stay on the stream.
    void draw_from(DimensionSource* source) { source_ = source; }

    // Uniform integer in [0, n), n > 0 (Lemire's nearly divisionless method, exact).
    uint32_t uniform_index(uint32_t n) {
        uint64_t m = uint64_t(next_u32()) * n;
        uint32_t l = static_cast<uint32_t>(m);
        if (l < n) {
            const uint32_t t = (0u - n) % n;
            while (l < t) {
                m = uint64_t(next_u32()) * n;
                l = static_cast<uint32_t>(m);
            }
        }
        return static_cast<uint32_t>(m >> 32);
    }

private:
    uint64_t state_ = 0;
    uint64_t inc_ = 1;
    DimensionSource* source_ = nullptr;
};

}  // namespace vpm
