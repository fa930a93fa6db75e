#include "config/transform_params.h"

#include <cmath>

namespace vpm {

Eigen::Affine3d read_transform(Params& table) {
    // "A number or a 3-array" is exactly what rgb() parses. Negative components mirror.
    const Rgb s = table.rgb("scale", Rgb::Ones());
    if ((s == 0.0).any()) table.fail("scale", "components must be non-zero");
    const std::vector<double> r = table.reals("rotate", {0.0, 0.0, 1.0, 0.0});
    if (r.size() != 4) table.fail("rotate", "expected [axis_x, axis_y, axis_z, degrees]");
    const Vec3 axis(r[0], r[1], r[2]);
    if (!(axis.norm() > 0.0) || !std::isfinite(axis.norm()) || !std::isfinite(r[3]))
        table.fail("rotate", "the rotation axis must be a finite non-zero vector and the angle finite");
    const Vec3 t = table.vec3("translate", Vec3::Zero());

    Eigen::Affine3d m = Eigen::Affine3d::Identity();
    m.translate(t);
    m.rotate(Eigen::AngleAxisd(r[3] * kPi / 180.0, axis.normalized()));
    m.scale(Vec3(s[0], s[1], s[2]));
    return m;
}

}  // namespace vpm
