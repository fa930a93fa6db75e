#include "scene/camera.h"

#include <cmath>
#include <sstream>

#include "core/error.h"

namespace vpm {

Camera::Camera(const Vec3& position, const Vec3& look_at, const Vec3& up, double fov_degrees, int width, int height)
    : position_(position), width_(width), height_(height) {
    forward_ = (look_at - position).normalized();
    right_ = forward_.cross(up).normalized();
    up_ = right_.cross(forward_);
    tan_half_fov_ = std::tan(0.5 * fov_degrees * kPi / 180.0);
}

Camera Camera::from_params(Params& p, int width, int height) {
    const Vec3 position = p.vec3("position", Vec3(0, 1, 4));
    const Vec3 look_at = p.vec3("look_at", Vec3(0, 1, 0));
    const Vec3 up = p.vec3("up", Vec3(0, 1, 0));
    const double fov = p.real("fov", 40.0, Range::open(0.0, 180.0));
    const Vec3 forward = look_at - position;
    if (forward.norm() == 0.0) p.fail("look_at", "must differ from camera.position");
    // The viewing direction is (look_at - position) normalised: its length must be a finite number.
    if (!std::isfinite(forward.norm()))
        p.fail("position", "is too far from camera.look_at: the distance between them must be below 1e154 (sqrt of "
                           "the largest double), so that the viewing direction can be computed");
    if (forward.normalized().cross(up).norm() < 1e-9) p.fail("up", "must not be parallel to the viewing direction");
    p.finish();
    return Camera(position, look_at, up, fov, width, height);
}

Ray Camera::generate_ray(double x, double y) const {
    const double aspect = double(width_) / double(height_);
    const double sx = (2.0 * x / width_ - 1.0) * tan_half_fov_ * aspect;
    const double sy = (1.0 - 2.0 * y / height_) * tan_half_fov_;
    return Ray{position_, (forward_ + sx * right_ + sy * up_).normalized()};
}

std::string Camera::describe() const {
    std::ostringstream s;
    s << "perspective camera at (" << position_.transpose() << "), " << width_ << "x" << height_
      << ", vertical fov " << 2.0 * std::atan(tan_half_fov_) * 180.0 / kPi << " deg";
    return s.str();
}

}  // namespace vpm
