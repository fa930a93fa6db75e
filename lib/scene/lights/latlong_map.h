#pragma once
// An environment map in latitude-longitude layout: radiance by direction, importance sampling of
// directions by luminance, and the integrals the environment light's power needs.
//
// Convention (+Y is up, as for the camera's default `up`): a W x H image, row 0 at the top.
// Texel (column i, row j) covers the polar angle theta from +Y in [pi j / H, pi (j+1) / H] and
// the azimuth phi in [2 pi i / W, 2 pi (i+1) / W], with
//
//     direction(theta, phi) = (-sin theta sin phi, cos theta, sin theta cos phi),
//
// so the top row is the zenith (+Y), the middle row the horizon, the image's centre column
// (phi = pi) looks along -Z (where the default camera looks), the column three quarters across
// along +X (to that camera's right), and the first and last columns along +Z: seen from inside,
// the panorama reads left to right as one turns right. `rotate_y` (degrees) turns the map about
// +Y by the right-hand rule, as a transform `rotate = [0, 1, 0, degrees]` does: what the
// unrotated map shows along -Z is shown along -X after rotate_y = 90.
//
// Radiance is constant over each texel (nearest-texel lookup) and so is the sampling density:
// a texel is chosen with probability proportional to luminance x its solid angle (rows weighted by
// cos theta_j - cos theta_j+1, i.e. by sin theta at the row centre, through
// core/sampling/piecewise_constant_2d.h), and a direction uniformly within its solid angle (phi uniform,
// cos theta uniform within the row). The solid-angle pdf is then constant over a texel,
//
//     pdf(w) = P(texel) / Omega(texel),  Omega = (2 pi / W) (cos theta_j - cos theta_j+1),
//
// (the limit of pbrt's p(u, v) / (2 pi^2 sin theta) for small texels, without dividing by sin theta
// at the poles), and radiance / pdf is the same for every direction of a texel: for a grey map it
// is the map's integral of luminance, for a constant map pdf = 1 / (4 pi) exactly.
#include <string>
#include <vector>

#include "core/math.h"
#include "core/sampling/piecewise_constant_2d.h"

namespace vpm {

// Unrotated map coordinates (u across, v down, both in [0, 1]) to the unit direction and back.
Vec3 latlong_direction(double u, double v);
void latlong_coordinates(const Vec3& dir, double& u, double& v);

class LatLongMap {
public:
    // `rgb`: 3 * width * height finite, non-negative values (the caller checks them), multiplied
    // by `scale`; the map is turned by `rotate_y_degrees` about +Y.
    LatLongMap(int width, int height, std::vector<float> rgb, const Rgb& scale, double rotate_y_degrees);

    int width() const { return width_; }
    int height() const { return height_; }
    // All texels black (after scale): nothing to sample, zero power.
    bool black() const { return distribution_.empty(); }

    // Radiance arriving from world direction dir (towards the sky), nearest texel.
    Rgb radiance(const Vec3& dir) const;
    // A direction towards the sky by luminance, with its radiance and solid-angle pdf (> 0).
    // Requires !black().
    void sample(double u1, double u2, Vec3& dir, Rgb& radiance, double& pdf) const;
    // The pdf with which sample() returns dir (0 for black texels).
    double pdf(const Vec3& dir) const;

    // Integral over the sphere of L(w) dw, and of L(w) |w_a| dw for a = x, y, z (world axes),
    // exact for the piecewise-constant map: an environment's emitted power into a box with face
    // areas A is sum_a A_a * abs_axis_integral(a) (scene/lights/emission_bounds.h).
    const Rgb& integral() const { return integral_; }
    const Rgb& abs_axis_integral(int axis) const { return abs_axis_integral_[axis]; }

private:
    void texel_of(const Vec3& dir, int& column, int& row) const;
    Rgb texel(int column, int row) const;
    double texel_pdf(int column, int row) const { return distribution_.probability(column, row) / row_solid_angle_[row]; }

    int width_ = 0, height_ = 0;
    std::vector<float> rgb_;
    Rgb scale_ = Rgb::Ones();
    double rotation_ = 0.0;                 // radians about +Y
    std::vector<double> row_cos_;           // cos theta at the row edges, height + 1 values
    std::vector<double> row_solid_angle_;   // solid angle of one texel of each row
    PiecewiseConstant2D distribution_;
    Rgb integral_ = Rgb::Zero();
    Rgb abs_axis_integral_[3] = {Rgb::Zero(), Rgb::Zero(), Rgb::Zero()};
};

}  // namespace vpm
