#pragma once
// The volume, first and second moments of a ball clipped by a box or by another ball, about the
// ball's centre: integral of 1, u and u u^T over the region, u = p - x. They are the sigma_t
// moments of a kNN ball in a homogeneous medium (photons.extinction = "linear",
// photon/estimate/ball_extinction.h), which took 64 lookups for a whole ball and 4096 (with an outer product
// each) for a clipped one (2.9x the thin cube's CPU).
//
//   ball in ball    a lens: two spherical caps glued at the plane of the spheres' circle; every
//                   term a polynomial in the cap heights (closed form).
//   ball in box     inclusion-exclusion over the faces the ball crosses (the centre inside the box,
//                   so every face cuts off a cap u_a > t with t >= 0): the ball, minus the caps,
//                   plus the intersections of two caps of different axes (edges), minus three
//                   (corners). A cap is closed form; two or three caps meet only where t_a^2 + t_b^2
//                   (+ t_c^2) < r^2, and there the region is integrated slice by slice: each slice
//                   is a disc cut by a quadrant, whose six moments are closed form, and the slices
//                   are summed by a tanh-sinh rule (25 nodes), which keeps its accuracy where the
//                   integrand has the square-root behaviour of a tangent slice (error below 1e-7
//                   of the ball's volume in the tests, against 0.2% for the 4096 points).
#include <Eigen/Core>

#include "core/math.h"

namespace vpm {

struct ClipMoments {
    double m0 = 0.0;                                  // volume
    Vec3 m1 = Vec3::Zero();                           // integral of u
    Eigen::Matrix3d m2 = Eigen::Matrix3d::Zero();     // integral of u u^T
};

// B(0, r) intersected with the box [lo, hi] given relative to the ball's centre. False if the
// centre is not inside the box (lo <= 0 <= hi in every axis): the caller integrates otherwise.
// The ball inside the box gives m1 exactly 0.
bool ball_box_moments(double r, const Vec3& lo, const Vec3& hi, ClipMoments& out);

// B(0, r) intersected with B(c, R).
ClipMoments ball_ball_moments(double r, const Vec3& c, double R);

}  // namespace vpm
