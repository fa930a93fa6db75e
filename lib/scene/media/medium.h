#pragma once
// A participating medium: extinction sigma_t(x) (grey), RGB single-scattering albedo and a
// Henyey-Greenstein g. Scattering coefficient = albedo * sigma_t.
//
// Free-flight sampling and transmittance are the only ways integrators touch sigma_t along a
// ray, so each medium can use its closed form (homogeneous) or delta / ratio tracking against
// a majorant (grids). Both are unbiased; nothing marches exp(-tau) with a fixed step.
#include <functional>
#include <memory>
#include <string>

#include "core/math.h"
#include "core/sampling/rng.h"
#include "scene/media/optical_depth_profile.h"

namespace vpm {

class Medium {
public:
    Medium(const Rgb& albedo, double g) : albedo_(albedo), g_(g) {}
    virtual ~Medium() = default;

    // World-space box outside which sigma_t is zero.
    virtual Bounds3 bounds() const = 0;

    // Distance to the first real collision along `ray` in (0, tmax), or kInfinity when the ray
    // leaves [0, tmax] without one. Distributed exactly as the free-flight distance.
    virtual double sample_free_flight(const Ray& ray, double tmax, Rng& rng) const = 0;

    // Unbiased estimate of exp(-integral_0^tmax sigma_t(ray(t)) dt); exact when a closed form exists.
    virtual double transmittance(const Ray& ray, double tmax, Rng& rng) const = 0;

    // Extinction at a point (1 / world length).
    virtual double sigma_t(const Vec3& p) const = 0;

    // The integral of sigma_t over the ball B(x, r) in closed form, when this medium has one there
    // (homogeneous: the ball inside the shape, a sphere's lens, a box face's cap; grid: the ball
    // inside one trilinear cell, whose mean is the centre value since every other term of the
    // trilinear polynomial is odd about it). False says nothing: the caller integrates
    // (photons.extinction = "ball", photon/estimate/ball_extinction.h).
    virtual bool ball_integral(const Vec3& x, double r, double& integral) const {
        (void)x;
        (void)r;
        (void)integral;
        return false;
    }
    // The sigma_t-weighted moments of B(x, r) about x in closed form, when this medium has one
    // (homogeneous: a sphere's lens, a box around x; scene/media/ball_clip_moments.h): m0 = the
    // integral of sigma_t, m1 of sigma_t (p - x), m2 of sigma_t (p - x)(p - x)^T. A ball inside a
    // homogeneous medium gives m1 exactly 0 (photons.extinction = "linear" then skips its weights).
    virtual bool ball_moments(const Vec3& x, double r, double& m0, Vec3& m1, Eigen::Matrix3d& m2) const {
        (void)x;
        (void)r;
        (void)m0;
        (void)m1;
        (void)m2;
        return false;
    }
    // sigma_t has no jump anywhere (it falls to 0 continuously at the bounds, like a trilinear
    // grid), so a quadrature of a ball crossing the bounds needs no clipping.
    virtual bool continuous() const { return false; }
    // The closed dielectric shape (its index among Surfaces::dielectric_shapes(), the bit of a region:
    // scene/dielectric_regions.h) this medium is confined to, or -1 for a medium that is where its
    // table puts it (scene/interior_medium.h).
    virtual int interior_of() const { return -1; }

    // The majorant along [0, tmax]: visit(ta, tb, majorant) for consecutive pieces in order of t,
    // each with majorant >= sigma_t on it (pieces with majorant 0 may be left out); stops when visit
    // returns false. Deterministic and cheap, so integrators can pick estimators and place points
    // per ray segment from geometry alone and stay unbiased.
    using MajorantVisitor = std::function<bool(double ta, double tb, double majorant)>;
    virtual void majorant_pieces(const Ray& ray, double tmax, const MajorantVisitor& visit) const = 0;

    // The exact optical depth along [0, tmax] as closed-form pieces (out is reset first), up to where
    // it reaches OpticalDepthProfile::kEnoughDepth or tmax. Deterministic; its work grows with the
    // voxel cells crossed, so callers use it where a majorant's looseness would cost more.
    virtual void optical_depth_profile(const Ray& ray, double tmax, OpticalDepthProfile& out) const = 0;

    // An upper bound on the optical depth along [0, tmax]: the integral of the majorant pieces.
    double majorant_optical_depth(const Ray& ray, double tmax) const {
        double depth = 0.0;
        majorant_pieces(ray, tmax, [&](double ta, double tb, double majorant) {
            depth += majorant * (tb - ta);
            return true;
        });
        return depth;
    }

    const Rgb& albedo() const { return albedo_; }
    double g() const { return g_; }

    // One line for logs and sidecars.
    virtual std::string describe() const = 0;

protected:
    Rgb albedo_;
    double g_;
};

}  // namespace vpm
