#include "scene/lights/latlong_map.h"

#include <algorithm>
#include <cmath>

namespace vpm {

namespace {

// World direction from the world azimuth phi and z = cos theta (the convention in latlong_map.h).
Vec3 direction_from(double phi, double cos_theta) {
    const double sin_theta = std::sqrt(std::max(0.0, 1.0 - cos_theta * cos_theta));
    return Vec3(-sin_theta * std::sin(phi), cos_theta, sin_theta * std::cos(phi));
}

// Antiderivatives over [0, a] of |sin| and |cos| (period pi, integral 2 per period), any real a.
double abs_sin_integral(double a) {
    const double k = std::floor(a / kPi), r = a - k * kPi;
    return 2.0 * k + (1.0 - std::cos(r));
}
double abs_cos_integral(double a) {
    const double k = std::floor(a / kPi), r = a - k * kPi;
    return 2.0 * k + (r <= 0.5 * kPi ? std::sin(r) : 2.0 - std::sin(r));
}
// Antiderivatives over [0, theta], theta in [0, pi], of |cos t| sin t and of sin^2 t.
double abs_cos_sin_integral(double t) {
    const double s2 = std::sin(t) * std::sin(t);
    return t <= 0.5 * kPi ? 0.5 * s2 : 1.0 - 0.5 * s2;
}
double sin2_integral(double t) { return 0.5 * t - 0.25 * std::sin(2.0 * t); }

}  // namespace

Vec3 latlong_direction(double u, double v) { return direction_from(2.0 * kPi * u, std::cos(kPi * v)); }

void latlong_coordinates(const Vec3& dir, double& u, double& v) {
    u = std::atan2(-dir.x(), dir.z()) / (2.0 * kPi);
    u -= std::floor(u);
    v = std::acos(std::min(1.0, std::max(-1.0, dir.y()))) / kPi;
}

LatLongMap::LatLongMap(int width, int height, std::vector<float> rgb, const Rgb& scale, double rotate_y_degrees)
    : width_(width), height_(height), rgb_(std::move(rgb)), scale_(scale), rotation_(rotate_y_degrees * kPi / 180.0) {
    row_cos_.resize(size_t(height_) + 1);
    for (int j = 0; j <= height_; ++j) row_cos_[size_t(j)] = std::cos(kPi * double(j) / double(height_));
    row_cos_.front() = 1.0;
    row_cos_.back() = -1.0;
    const double dphi = 2.0 * kPi / double(width_);
    row_solid_angle_.resize(size_t(height_));
    for (int j = 0; j < height_; ++j) row_solid_angle_[size_t(j)] = dphi * (row_cos_[size_t(j)] - row_cos_[size_t(j) + 1]);

    // Per-column integrals of |w_x| / sin theta and |w_z| / sin theta over the texel's world azimuths.
    std::vector<double> col_x(static_cast<size_t>(width_)), col_z(static_cast<size_t>(width_));
    for (int i = 0; i < width_; ++i) {
        const double p0 = dphi * double(i) - rotation_, p1 = dphi * double(i + 1) - rotation_;
        col_x[size_t(i)] = abs_sin_integral(p1) - abs_sin_integral(p0);   // |x| = sin theta |sin phi|
        col_z[size_t(i)] = abs_cos_integral(p1) - abs_cos_integral(p0);   // |z| = sin theta |cos phi|
    }

    std::vector<double> weights(size_t(width_) * size_t(height_));
    for (int j = 0; j < height_; ++j) {
        const double t0 = kPi * double(j) / double(height_), t1 = kPi * double(j + 1) / double(height_);
        const double row_y = abs_cos_sin_integral(t1) - abs_cos_sin_integral(t0);   // of |cos theta| sin theta
        const double row_xz = sin2_integral(t1) - sin2_integral(t0);               // of sin theta * sin theta
        for (int i = 0; i < width_; ++i) {
            const Rgb L = texel(i, j);
            weights[size_t(j) * size_t(width_) + size_t(i)] = luminance(L) * row_solid_angle_[size_t(j)];
            integral_ += L * row_solid_angle_[size_t(j)];
            abs_axis_integral_[0] += L * (row_xz * col_x[size_t(i)]);
            abs_axis_integral_[1] += L * (row_y * dphi);
            abs_axis_integral_[2] += L * (row_xz * col_z[size_t(i)]);
        }
    }
    distribution_ = PiecewiseConstant2D(width_, height_, weights);
}

Rgb LatLongMap::texel(int column, int row) const {
    const size_t k = 3 * (size_t(row) * size_t(width_) + size_t(column));
    return Rgb(rgb_[k], rgb_[k + 1], rgb_[k + 2]) * scale_;
}

void LatLongMap::texel_of(const Vec3& dir, int& column, int& row) const {
    double u, v;
    latlong_coordinates(dir, u, v);   // world coordinates; the map is turned by rotation_
    u += rotation_ / (2.0 * kPi);
    u -= std::floor(u);
    column = std::min(std::max(int(u * double(width_)), 0), width_ - 1);
    row = std::min(std::max(int(v * double(height_)), 0), height_ - 1);
}

Rgb LatLongMap::radiance(const Vec3& dir) const {
    int column, row;
    texel_of(dir, column, row);
    return texel(column, row);
}

void LatLongMap::sample(double u1, double u2, Vec3& dir, Rgb& radiance, double& pdf) const {
    const PiecewiseConstant2D::Sample s = distribution_.sample(u1, u2);
    // Uniform in solid angle within the texel: phi uniform, cos theta uniform between the row's edges.
    const double fv = std::min(std::max(s.v * double(height_) - double(s.row), 0.0), 1.0);
    const double cos_theta = row_cos_[size_t(s.row)] + fv * (row_cos_[size_t(s.row) + 1] - row_cos_[size_t(s.row)]);
    dir = direction_from(2.0 * kPi * s.u - rotation_, cos_theta);
    radiance = texel(s.column, s.row);
    pdf = texel_pdf(s.column, s.row);
}

double LatLongMap::pdf(const Vec3& dir) const {
    if (black()) return 0.0;
    int column, row;
    texel_of(dir, column, row);
    return texel_pdf(column, row);
}

}  // namespace vpm
