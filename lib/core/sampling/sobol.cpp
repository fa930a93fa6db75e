#include "core/sampling/sobol.h"

#include <vector>

#include <boost/random/detail/sobol_table.hpp>

#include "core/error.h"

namespace vpm {

namespace {

// Bratley & Fox's recurrence (ACM TOMS 14, 1988) on the direction numbers v_j = m_j / 2^j, from
// the primitive polynomial x^s + a_1 x^(s-1) + ... + a_(s-1) x + 1 and the initial m_1..m_s.
std::vector<uint32_t> build_matrices() {
    using Table = boost::random::detail::qrng_tables::sobol;
    static_assert(kSobolDimensions <= int(Table::max_dimension), "more Sobol dimensions than the table holds");
    std::vector<uint32_t> m(size_t(kSobolDimensions) * 32, 0);
    for (int j = 0; j < 32; ++j) m[size_t(j)] = 1u << (31 - j);   // dimension 0: the identity
    for (int d = 1; d < kSobolDimensions; ++d) {
        uint32_t* v = &m[size_t(d) * 32];
        const unsigned poly = Table::polynomial(size_t(d - 1));
        int s = 0;
        while ((poly >> (s + 1)) != 0) ++s;   // the degree
        for (int j = 0; j < s && j < 32; ++j) v[j] = uint32_t(Table::minit(size_t(d - 1), size_t(j))) << (31 - j);
        for (int j = s; j < 32; ++j) {
            uint32_t x = v[j - s] ^ (v[j - s] >> s);
            for (int i = 1; i < s; ++i)
                if ((poly >> (s - i)) & 1u) x ^= v[j - i];
            v[j] = x;
        }
    }
    return m;
}

const std::vector<uint32_t>& matrices() {
    static const std::vector<uint32_t> m = build_matrices();
    return m;
}

}  // namespace

const uint32_t* sobol_matrix(int dim) {
    if (dim < 0 || dim >= kSobolDimensions) throw Error("sobol: dimension " + std::to_string(dim) + " out of range");
    return &matrices()[size_t(dim) * 32];
}

uint32_t sobol_bits(uint32_t index, int dim) {
    const uint32_t* v = &matrices()[size_t(dim) * 32];
    uint32_t x = 0;
    for (int j = 0; index; ++j, index >>= 1)
        if (index & 1u) x ^= v[j];
    return x;
}

}  // namespace vpm
