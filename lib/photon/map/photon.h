#pragma once
// The compact stored photon record and its codecs.
//
// A photon is stored where it collided inside a medium: position, the direction it was travelling
// when it arrived (incoming *travel* direction, the d_in of hg_eval), and its RGB power in watts.
//
// Layout (24 bytes, 4-byte aligned):
//   float    p[3]      position relative to the photon map's bounds centre (12 bytes)
//   uint16_t dir[2]    octahedral direction, 2 x 16 bit                      ( 4 bytes)
//   uint16_t power[3]  IEEE binary16 per channel of power / 2^e               ( 6 bytes)
//   uint16_t reserved  low 12 bits: the exponent e (signed) of the photon's     ( 2 bytes)
//                      largest channel; high 4 bits: its walk group (below)
// plus 4 bytes per photon for its walk (uint32, photon_map.h: the records sit in the kd-tree's leaf
// order, so the tree needs no permutation array and that slot holds the walk) = 28 bytes per photon,
// see bytes_per_photon(). The kd-tree nodes add ~3 bytes per photon on top (32-byte nodes, one
// per ~11 photons at leaf size 32): 30.8-31.1 bytes per photon in total (PhotonMap::memory_bytes(),
// tests/photon/map/photon_codec_test.cpp holds it at <= 32).
//
// Error bounds (tested in tests/photon/test_photon_codec.cpp):
//   position  : |error| per axis <= 2^-24 * max(|p - centre|) over the axes (float rounding of the
//               offset from the centre, so scenes far from the origin keep full precision).
//   direction : angular error <= 7e-5 rad (octahedral grid step 2/65535, rounded to nearest;
//               the octahedral map stretches the grid by ~2x; measured max 6.4e-5 rad).
//   power     : each channel is divided by 2^e, e the binary exponent of the photon's own largest
//               channel (stored in `reserved`, so the largest is in [1, 2)), and rounded to binary16:
//               relative error <= 2^-11 per channel for values >= 2^-14 * 2^e; below that
//               (subnormals) the absolute error is <= 2^-25 * 2^e. Channels are independent (no
//               shared exponent), so a dim channel next to a bright one keeps its own relative
//               precision, and photons of any power share one map: an earlier map-wide scale (the
//               largest channel of any photon) flushed photons 2^24 times dimmer than the brightest
//               to zero or to coarse subnormals (a point light's photons next to a sky
//               light's in one map came out 2x too bright).
// Walks: every stored photon knows its walk (the emitted path that stored it; PhotonInput::walk,
// PhotonMap::walk), so the walk-neighbour estimate (photon/estimate/walk_estimate.h) can count
// independent walks instead of correlated photons. Walk groups: the photons of one emitted path
// share a group, its path index mod kWalkGroups (= walk mod kWalkGroups for the tracer's photons),
// kept in `reserved` so that the leave-group-out estimator (photon/estimate/group_estimate.h) and
// split_by_walk_group read it without a division. A double's binary exponent (-1074 .. 1023) fits
// the 12 bits left.
#include <Eigen/Core>
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cmath>
#include <cstring>

#include "core/math.h"

namespace vpm {

constexpr int kWalkGroups = 16;

// Double-precision photon as produced by the photon tracer; input for building a PhotonMap.
struct PhotonInput {
    Vec3 position = Vec3::Zero();
    Vec3 direction = Vec3::UnitZ();   // incoming travel direction, unit length
    Rgb power = Rgb::Zero();          // watts
    uint8_t group = 0;                // walk group, < kWalkGroups
    // The walk (emitted path) that stored this photon: photons with equal labels belong to one
    // walk, any other label is another, independent walk. The tracer uses the path index in its
    // pass. The map keeps a dense id per distinct label (PhotonMap::walk).
    uint64_t walk = 0;
};

struct Photon {
    float p[3];
    uint16_t dir[2];
    uint16_t power[3];
    uint16_t reserved;
};
static_assert(sizeof(Photon) == 24, "Photon record must stay 24 bytes");

// Bytes per stored photon: the record plus its uint32 walk id.
// (kd-tree nodes are extra: measured by PhotonMap::memory_bytes(), ~2-3 bytes per photon.)
constexpr size_t bytes_per_photon() { return sizeof(Photon) + sizeof(uint32_t); }

// --- octahedral direction codec -----------------------------------------------------------------
inline uint16_t oct_quantize(double v) {   // v in [-1, 1] -> [0, 65535], round to nearest
    const double t = std::min(1.0, std::max(-1.0, v));
    return static_cast<uint16_t>(std::lround((t * 0.5 + 0.5) * 65535.0));
}
inline double oct_dequantize(uint16_t q) { return (double(q) / 65535.0) * 2.0 - 1.0; }

inline void encode_direction(const Vec3& d, uint16_t out[2]) {
    const double l1 = std::abs(d.x()) + std::abs(d.y()) + std::abs(d.z());
    if (!(l1 > 0.0)) {   // zero or NaN direction: store +z
        out[0] = oct_quantize(0.0);
        out[1] = oct_quantize(0.0);
        return;
    }
    double u = d.x() / l1, v = d.y() / l1;
    if (d.z() < 0.0) {
        const double su = u >= 0.0 ? 1.0 : -1.0, sv = v >= 0.0 ? 1.0 : -1.0;
        const double nu = (1.0 - std::abs(v)) * su;
        const double nv = (1.0 - std::abs(u)) * sv;
        u = nu;
        v = nv;
    }
    out[0] = oct_quantize(u);
    out[1] = oct_quantize(v);
}

inline Vec3 decode_direction(const uint16_t in[2]) {
    const double u = oct_dequantize(in[0]), v = oct_dequantize(in[1]);
    Vec3 d(u, v, 1.0 - std::abs(u) - std::abs(v));
    if (d.z() < 0.0) {
        const double su = u >= 0.0 ? 1.0 : -1.0, sv = v >= 0.0 ? 1.0 : -1.0;
        d.x() = (1.0 - std::abs(v)) * su;
        d.y() = (1.0 - std::abs(u)) * sv;
    }
    return d.normalized();
}

// --- binary16 power codec ------------------------------------------------------------------------
inline uint16_t encode_half(double v) {
    const Eigen::half h(static_cast<float>(v));   // round to nearest even
    return Eigen::numext::bit_cast<uint16_t>(h);
}
inline double decode_half(uint16_t bits) {
    return static_cast<double>(static_cast<float>(Eigen::numext::bit_cast<Eigen::half>(bits)));
}

// scale > 0 (the photon map passes 2^e, power_exponent below); inv_scale = 1/scale.
inline void encode_power(const Rgb& power, double inv_scale, uint16_t out[3]) {
    for (int c = 0; c < 3; ++c) out[c] = encode_half(std::max(0.0, power[c]) * inv_scale);
}
inline Rgb decode_power(const uint16_t in[3], double scale) {
    return Rgb(decode_half(in[0]), decode_half(in[1]), decode_half(in[2])) * scale;
}

// e with 2^e <= the largest channel < 2^(e+1); 0 for a zero (or non-finite) power.
inline int16_t power_exponent(const Rgb& power) {
    const double m = power.maxCoeff();
    if (!(m > 0.0) || !std::isfinite(m)) return 0;
    return static_cast<int16_t>(std::ilogb(m));
}
// `reserved`: e in the low 12 bits (two's complement), the walk group in the high 4.
inline uint16_t exponent_bits(int16_t e, uint8_t group = 0) {
    return static_cast<uint16_t>((uint16_t(e) & 0x0fffu) | (uint16_t(group & 0x0fu) << 12));
}
inline double exponent_scale(uint16_t bits) {
    const int e = int(bits & 0x0fffu) - ((bits & 0x0800u) ? 0x1000 : 0);   // sign-extend 12 bits
    return std::ldexp(1.0, e);
}
inline uint8_t walk_group(uint16_t bits) { return static_cast<uint8_t>(bits >> 12); }

}  // namespace vpm
