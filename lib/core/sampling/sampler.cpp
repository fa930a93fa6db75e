#include "core/sampling/sampler.h"

#include <cmath>
#include <string>

#include "core/error.h"
#include "core/sampling/hashed_permutation.h"
#include "core/sampling/owen_scramble.h"
#include "core/sampling/sobol.h"

namespace vpm {

namespace {

constexpr uint64_t kDimSpread = 0xd1b54a32d192ed03ULL;

// A uniform double in [0, 1) from a hash of (key, index, dim).
double hashed_uniform(uint64_t key, uint64_t index, uint32_t dim) {
    return double(mix64(mix64(key ^ (uint64_t(dim) * kDimSpread)) + index) >> 11) * 0x1.0p-53;
}

}  // namespace

PathSampler::PathSampler(SamplerKind kind, uint64_t key, uint64_t set_size) : kind_(kind), key_(key), n_(set_size) {
    if (n_ == 0) throw Error("sampler: a sample set needs at least one vector");
    if (kind_ == SamplerKind::stratified) {
        if (n_ > (uint64_t(1) << 31))
            throw Error("sampler \"stratified\": at most 2^31 vectors per set (" + std::to_string(n_) + " asked)");
        // nx x ny >= n cells, as square as possible: an exact factorisation when one is near the
        // square root, else floor(sqrt n) columns and enough rows (cells left empty at random).
        const uint64_t root = uint64_t(std::floor(std::sqrt(double(n_))));
        uint64_t nx = root;
        while (nx > 1 && n_ % nx != 0) --nx;
        if (2 * nx < root) nx = root;
        nx_ = uint32_t(std::max<uint64_t>(nx, 1));
        ny_ = uint32_t((n_ + nx_ - 1) / nx_);
    }
    if (kind_ == SamplerKind::sobol) {
        if (n_ >= (uint64_t(1) << 32))
            throw Error("sampler \"sobol\": at most 2^32 - 1 vectors per set (" + std::to_string(n_) + " asked)");
        depth_ = scramble_depth(n_);
    }
}

double PathSampler::sample(uint64_t index, uint32_t dim) const {
    switch (kind_) {
        case SamplerKind::independent:
            return hashed_uniform(key_, index, dim);
        case SamplerKind::stratified: {
            const uint32_t pair = dim / 2;
            const uint64_t pair_key = mix64(key_ ^ (uint64_t(pair) * kDimSpread) ^ 0x7374726174ULL);
            const uint32_t cell = permutation_element(uint32_t(index), nx_ * ny_, pair_key);
            const double jitter = hashed_uniform(key_, index, dim);
            return dim % 2 == 0 ? (double(cell % nx_) + jitter) / double(nx_)
                                : (double(cell / nx_) + jitter) / double(ny_);
        }
        case SamplerKind::sobol: {
            const uint64_t dim_key = mix64(key_ ^ (uint64_t(dim) * kDimSpread) ^ 0x736f626f6cULL);
            uint32_t i = uint32_t(index);
            if (dim >= uint32_t(kSobolDimensions)) i = permutation_element(i, uint32_t(n_), dim_key);
            return owen_scrambled_uniform(sobol_bits(i, int(dim % uint32_t(kSobolDimensions))), dim_key, depth_);
        }
    }
    return 0.0;
}

}  // namespace vpm
