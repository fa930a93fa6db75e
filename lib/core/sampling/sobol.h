#pragma once
// Sobol' points (Sobol' 1967) from the direction numbers of Joe & Kuo, "Constructing Sobol sequences
// with better two-dimensional projections", SIAM J. Sci. Comput. 30 (2008), file new-joe-kuo-6.21201.
// The numbers are data Debian already ships: Boost.Random's table (boost/random/detail/sobol_table.hpp,
// libboost-dev), which this reads; nothing is copied. Dimension 0 is van der Corput's radical
// inverse, dimensions 0 and 1 together a (0, 2)-sequence in base 2, and every dimension alone a
// (0, 1)-sequence: its first 2^m points hold one point in each interval [j 2^-m, (j + 1) 2^-m).
#include <cstdint>

namespace vpm {

// Dimensions with their own generator matrix; samplers pad beyond them (core/sampling/sampler.h).
constexpr int kSobolDimensions = 1024;

// Point `index` (< 2^32) of dimension `dim` (< kSobolDimensions) as a 32-bit binary fraction
// (bit 31 is 1/2), unscrambled.
uint32_t sobol_bits(uint32_t index, int dim);

// The generator matrix of `dim`: 32 columns, column j is the image of index bit j.
const uint32_t* sobol_matrix(int dim);

}  // namespace vpm
