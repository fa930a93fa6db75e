#pragma once
// An integrator estimates the radiance arriving along a camera ray. Estimates must be
// independent across calls given independent Rng streams; the render loop averages them.
#include <string>

#include "core/math.h"
#include "core/rng.h"

namespace vpm {

class Integrator {
public:
    virtual ~Integrator() = default;
    // Radiance travelling towards the camera along -ray.dir.
    virtual Rgb radiance(const Ray& ray, Rng& rng) const = 0;
    virtual std::string name() const = 0;
};

}  // namespace vpm
