#include "scene/media/ball_clip_moments.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace vpm {

namespace {

// Moments in a canonical frame (x', y', z'), mapped back by the signed permutation u' = P u.
ClipMoments to_frame(const ClipMoments& c, const Eigen::Matrix3d& P) {
    ClipMoments out;
    out.m0 = c.m0;
    out.m1 = P.transpose() * c.m1;
    out.m2 = P.transpose() * c.m2 * P;
    return out;
}

void add(ClipMoments& a, const ClipMoments& b, double sign) {
    a.m0 += sign * b.m0;
    a.m1 += sign * b.m1;
    a.m2 += sign * b.m2;
}

ClipMoments whole_ball(double r) {
    ClipMoments m;
    m.m0 = (4.0 / 3.0) * kPi * r * r * r;
    m.m2 = Eigen::Matrix3d::Identity() * (4.0 / 15.0) * kPi * std::pow(r, 5);
    return m;
}

// The cap {u . n > t} of B(0, r), |t| < r, n a unit vector: slices along n are discs of radius^2
// r^2 - s^2, integrated over s in [t, r] (polynomials).
ClipMoments cap(double r, double t, const Vec3& n) {
    const double r2 = r * r;
    auto poly = [&](double s, int which) {
        const double s2 = s * s;
        switch (which) {
            case 0: return r2 * s - s * s2 / 3.0;                                   // integral of rho^2
            case 1: return r2 * s2 / 2.0 - s2 * s2 / 4.0;                            // of s rho^2
            case 2: return r2 * s * s2 / 3.0 - s2 * s2 * s / 5.0;                    // of s^2 rho^2
            default: return r2 * r2 * s - 2.0 * r2 * s * s2 / 3.0 + s2 * s2 * s / 5.0;   // of rho^4
        }
    };
    const double a0 = kPi * (poly(r, 0) - poly(t, 0));
    const double a1 = kPi * (r2 - t * t) * (r2 - t * t) / 4.0;
    const double a2 = kPi * (poly(r, 2) - poly(t, 2));
    const double p = 0.25 * kPi * (poly(r, 3) - poly(t, 3));   // a disc's second moment is pi rho^4 / 4 per axis
    ClipMoments m;
    m.m0 = a0;
    m.m1 = a1 * n;
    const Eigen::Matrix3d nn = n * n.transpose();
    m.m2 = a2 * nn + p * (Eigen::Matrix3d::Identity() - nn);
    return m;
}

// The six moments (area, x, y, xx, yy, xy) of the disc x^2 + y^2 < rho2 cut by x > a, y > b
// (a, b >= 0): over x in [a, sqrt(rho2 - b^2)], y in [b, s(x)], s = sqrt(rho2 - x^2).
struct Slice {
    double A = 0, x = 0, y = 0, xx = 0, yy = 0, xy = 0;
};
Slice quadrant(double rho2, double a, double b) {
    Slice q;
    if (!(rho2 > a * a + b * b)) return q;
    const double rho = std::sqrt(rho2);
    const double xb = std::sqrt(rho2 - b * b);
    auto S = [&](double x, double& s0, double& s1, double& s2, double& s3) {
        const double s = std::sqrt(std::max(0.0, rho2 - x * x));
        const double as = std::asin(std::min(1.0, x / rho));
        s0 = 0.5 * (x * s + rho2 * as);
        s1 = -s * s * s / 3.0;
        s2 = x * (2.0 * x * x - rho2) * s / 8.0 + rho2 * rho2 * as / 8.0;
        s3 = x * s * s * s / 4.0 + 3.0 * rho2 * x * s / 8.0 + 3.0 * rho2 * rho2 * as / 8.0;
    };
    double h0, h1, h2, h3, l0, l1, l2, l3;
    S(xb, h0, h1, h2, h3);
    S(a, l0, l1, l2, l3);
    const double d1 = xb - a, d2 = xb * xb - a * a, d3 = xb * xb * xb - a * a * a, d4 = xb * xb * xb * xb - a * a * a * a;
    q.A = (h0 - l0) - b * d1;
    q.x = (h1 - l1) - b * d2 / 2.0;
    q.y = 0.5 * (rho2 * d1 - d3 / 3.0 - b * b * d1);
    q.xx = (h2 - l2) - b * d3 / 3.0;
    q.yy = ((h3 - l3) - b * b * b * d1) / 3.0;
    q.xy = 0.5 * (rho2 * d2 / 2.0 - d4 / 4.0 - b * b * d2 / 2.0);
    return q;
}

// Tanh-sinh nodes on (-1, 1): x_k = tanh(pi/2 sinh t_k), t_k = k h; c_k = 1 - |x_k| kept apart so
// that nodes next to an endpoint are placed without cancellation.
constexpr int kHalfNodes = 12;
constexpr double kStep = 0.25;
struct Node {
    double x, c, w;
};
const std::array<Node, 2 * kHalfNodes + 1>& tanh_sinh() {
    static const std::array<Node, 2 * kHalfNodes + 1> nodes = [] {
        std::array<Node, 2 * kHalfNodes + 1> n{};
        for (int k = -kHalfNodes; k <= kHalfNodes; ++k) {
            const double t = k * kStep, u = 0.5 * kPi * std::sinh(t);
            const double e = std::exp(-2.0 * std::abs(u));
            const double ch = std::cosh(u);
            n[size_t(k + kHalfNodes)] = Node{std::tanh(u), 2.0 * e / (1.0 + e), kStep * 0.5 * kPi * std::cosh(t) / (ch * ch)};
        }
        return n;
    }();
    return nodes;
}

// The region of B(0, r) with x' > a, y' > b, z' in [z0, z1] (a, b >= 0), slice by slice along z'.
ClipMoments quadrant_prism(double r, double a, double b, double z0, double z1) {
    ClipMoments m;
    if (!(z1 > z0)) return m;
    const double half = 0.5 * (z1 - z0);
    double A = 0, X = 0, Y = 0, Z = 0, XX = 0, YY = 0, XY = 0, ZZ = 0, XZ = 0, YZ = 0;
    for (const Node& n : tanh_sinh()) {
        const double z = n.x >= 0.0 ? z1 - half * n.c : z0 + half * n.c;
        const Slice q = quadrant(r * r - z * z, a, b);
        const double w = half * n.w;
        A += w * q.A;
        X += w * q.x;
        Y += w * q.y;
        Z += w * z * q.A;
        XX += w * q.xx;
        YY += w * q.yy;
        XY += w * q.xy;
        ZZ += w * z * z * q.A;
        XZ += w * z * q.x;
        YZ += w * z * q.y;
    }
    m.m0 = A;
    m.m1 = Vec3(X, Y, Z);
    m.m2 << XX, XY, XZ, XY, YY, YZ, XZ, YZ, ZZ;
    return m;
}

struct Cut {
    int axis;
    double sign;   // the cap is sign * u_axis > t
    double t;      // >= 0
};

// The signed permutation with rows (first cut's axis, second's, the remaining axis).
Eigen::Matrix3d frame(const Cut& c1, const Cut& c2, int third_axis, double third_sign) {
    Eigen::Matrix3d P = Eigen::Matrix3d::Zero();
    P(0, c1.axis) = c1.sign;
    P(1, c2.axis) = c2.sign;
    P(2, third_axis) = third_sign;
    return P;
}

}  // namespace

bool ball_box_moments(double r, const Vec3& lo, const Vec3& hi, ClipMoments& out) {
    if ((lo.array() > 0.0).any() || (hi.array() < 0.0).any() || !(r > 0.0)) return false;
    std::array<Cut, 6> cuts;
    int n = 0;
    for (int a = 0; a < 3; ++a) {
        if (hi[a] < r) cuts[size_t(n++)] = Cut{a, 1.0, hi[a]};
        if (-lo[a] < r) cuts[size_t(n++)] = Cut{a, -1.0, -lo[a]};
    }
    out = whole_ball(r);
    const double r2 = r * r;
    for (int i = 0; i < n; ++i) {
        Vec3 normal = Vec3::Zero();
        normal[cuts[size_t(i)].axis] = cuts[size_t(i)].sign;
        add(out, cap(r, cuts[size_t(i)].t, normal), -1.0);
    }
    // Caps of one axis are disjoint (the centre lies between the faces); caps of different axes
    // overlap where the sum of their squared offsets is below r^2.
    for (int i = 0; i < n; ++i)
        for (int j = i + 1; j < n; ++j) {
            const Cut &ci = cuts[size_t(i)], &cj = cuts[size_t(j)];
            if (ci.axis == cj.axis) continue;
            const double zz = r2 - ci.t * ci.t - cj.t * cj.t;
            if (!(zz > 0.0)) continue;
            const int free_axis = 3 - ci.axis - cj.axis;
            const double Z = std::sqrt(zz);
            add(out, to_frame(quadrant_prism(r, ci.t, cj.t, -Z, Z), frame(ci, cj, free_axis, 1.0)), 1.0);
            for (int l = j + 1; l < n; ++l) {
                const Cut& cl = cuts[size_t(l)];
                if (cl.axis == ci.axis || cl.axis == cj.axis || !(cl.t < Z)) continue;
                add(out, to_frame(quadrant_prism(r, ci.t, cj.t, cl.t, Z), frame(ci, cj, cl.axis, cl.sign)), -1.0);
            }
        }
    if (n == 0) out.m1 = Vec3::Zero();   // exactly: nothing is cut
    return true;
}

ClipMoments ball_ball_moments(double r, const Vec3& c, double R) {
    const double d = c.norm();
    ClipMoments m;
    if (d >= r + R) return m;
    if (d + r <= R) return whole_ball(r);
    if (d + R <= r) {
        m = whole_ball(R);
        m.m1 = m.m0 * c;
        m.m2 += m.m0 * (c * c.transpose());
        return m;
    }
    const Vec3 n = c / d;
    const double s0 = (d * d + r * r - R * R) / (2.0 * d);   // the plane of the two spheres' circle, along n
    m = cap(r, s0, n);                                        // our ball beyond the plane
    const ClipMoments o = cap(R, d - s0, -n);                 // the other ball on our side of it, about c
    m.m0 += o.m0;
    m.m1 += o.m1 + o.m0 * c;
    m.m2 += o.m2 + o.m1 * c.transpose() + c * o.m1.transpose() + o.m0 * (c * c.transpose());
    return m;
}

}  // namespace vpm
