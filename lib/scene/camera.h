#pragma once
// Pinhole perspective camera. Parameters (table [camera]):
//   position = [x,y,z]   look_at = [x,y,z]   up = [0,1,0]   fov = 40 (vertical, degrees, (0,180))
#include <string>

#include "core/math.h"
#include "config/params.h"

namespace vpm {

class Camera {
public:
    Camera() = default;
    Camera(const Vec3& position, const Vec3& look_at, const Vec3& up, double fov_degrees, int width, int height);
    static Camera from_params(Params& p, int width, int height);

    // Ray through image position (x, y) in pixels, (0,0) the top-left corner of the image.
    Ray generate_ray(double x, double y) const;
    std::string describe() const;
    int width() const { return width_; }
    int height() const { return height_; }

private:
    Vec3 position_ = Vec3::Zero();
    Vec3 forward_ = -Vec3::UnitZ(), right_ = Vec3::UnitX(), up_ = Vec3::UnitY();
    double tan_half_fov_ = 1.0;
    int width_ = 1, height_ = 1;
};

}  // namespace vpm
