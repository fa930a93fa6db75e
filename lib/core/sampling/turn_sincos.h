#pragma once
// cos(2 pi u) and sin(2 pi u) for an azimuth given as a fraction u of a turn, u in [0, 1) (any
// finite u works; accuracy is for |u| < 2^20). The samplers' azimuths are uniforms in [0, 1), and
// glibc's sincos was 8-11% of photon tracing (docs/studies/photon_tracing.md section 14): its argument reduction
// is for any angle in radians, while a fraction of a turn reduces exactly to an octant.
//
// 4u - q, with q the integer nearest to 4u,, is exact (Sterbenz), so the only rounding before the
// polynomials is x = (4u - q) pi / 2, |x| <= pi / 4. There the Taylor series of sin and cos up to
// x^17 and x^18 are within 1e-19 of the functions, so results are within a few ulps of the
// correctly rounded ones. The quarter turns q are then exact swaps and sign flips.
#include <cmath>

namespace vpm {

struct SinCos {
    double sin, cos;
};

inline SinCos sincos_turns(double u) {
    const double v = 4.0 * u;
    // Round to nearest by the 1.5 * 2^52 shift (exact for |v| < 2^51; no libm call without SSE4.1).
    const double q = (v + 6755399441055744.0) - 6755399441055744.0;
    const double x = (v - q) * 1.5707963267948966;   // pi / 2
    const double x2 = x * x;
    // Horner in x^2 with the coefficients 1/n! (signs alternating).
    double ps = 2.8114572543455206e-15;               //  1/17!
    ps = ps * x2 - 7.6471637318198164e-13;            // -1/15!
    ps = ps * x2 + 1.6059043836821613e-10;            //  1/13!
    ps = ps * x2 - 2.5052108385441720e-08;            // -1/11!
    ps = ps * x2 + 2.7557319223985893e-06;            //  1/9!
    ps = ps * x2 - 1.9841269841269841e-04;            // -1/7!
    ps = ps * x2 + 8.3333333333333333e-03;            //  1/5!
    ps = ps * x2 - 1.6666666666666666e-01;            // -1/3!
    const double s = x + x * x2 * ps;
    double pc = 1.5619206968586225e-16;               //  1/18!
    pc = pc * x2 - 4.7794773323873853e-14;            // -1/16!
    pc = pc * x2 + 1.1470745597729725e-11;            //  1/14!
    pc = pc * x2 - 2.0876756987868099e-09;            // -1/12!
    pc = pc * x2 + 2.7557319223985888e-07;            //  1/10!
    pc = pc * x2 - 2.4801587301587302e-05;            // -1/8!
    pc = pc * x2 + 1.3888888888888889e-03;            //  1/6!
    pc = pc * x2 - 4.1666666666666664e-02;            // -1/4!
    pc = pc * x2 + 0.5;                               //  1/2!  (subtracted below)
    const double c = 1.0 - x2 * pc;
    // Quarter turns: (cos, sin) rotated by q * 90 degrees, without branches (q is random).
    const int k = static_cast<int>(static_cast<long long>(q) & 3);
    const bool swap = k & 1;
    const double a = swap ? c : s, b = swap ? s : c;
    return {double(1 - (k & 2)) * a, double(1 - ((k + 1) & 2)) * b};
}

}  // namespace vpm
