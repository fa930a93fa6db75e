#pragma once
// Chandrasekhar's H function for isotropic scattering, and the radiance a semi-infinite
// homogeneous medium reflects (Chandrasekhar, Radiative Transfer, 1950, ch. IV).
//
// A half-space of single-scattering albedo a with isotropic scattering, lit by a collimated beam of
// irradiance E (measured perpendicular to the beam) at incidence mu0 = cos(theta0), reflects in
// direction mu = cos(theta) (both measured from the outward normal) the radiance
//
//     L(mu, mu0) = a / (4 pi) * E * mu0 / (mu + mu0) * H(mu) * H(mu0)        (all orders)
//
// with H the solution of   1 / H(mu) = sqrt(1 - a) + (a / 2) int_0^1 mu' H(mu') / (mu + mu') dmu'
// (the form whose fixed-point iteration converges for every a in [0, 1]). Its single-scattering
// part is a / (4 pi) E mu0 / (mu + mu0). Neither integrator wrote this: it is the analytic anchor.
//
// Solved by Nystrom's method on Gauss-Legendre nodes in t with mu' = t^2 (H has a mu log mu term
// at 0, which the substitution smooths), Newton's method until a step is < 1e-14; H at
// any mu comes from the equation itself with the converged node values. Accuracy (checked in
// tests/analysis/study/chandrasekhar_h_test.cpp against the moment identity
// int_0^1 H = (2 / a) (1 - sqrt(1 - a)), the conservative int_0^1 H mu = 2 / sqrt(3) and
// Chandrasekhar's table): better than 1e-9 with the default 64 nodes.
#include <vector>

namespace vpm {

class ChandrasekharH {
public:
    // albedo in [0, 1]; throws vpm::Error otherwise. nodes >= 8.
    explicit ChandrasekharH(double albedo, int nodes = 64);
    double albedo() const { return albedo_; }
    // H(mu) for mu in [0, 1] (throws vpm::Error outside).
    double operator()(double mu) const;
    // int_0^1 H(mu) mu^n dmu by the solver's own quadrature (n = 0, 1): the moments the tests check.
    double moment(int n) const;
    // The reflected radiance above, per unit irradiance E.
    double reflected(double mu, double mu0) const;
    // Its single-scattering part a / (4 pi) mu0 / (mu + mu0).
    double single_scattering(double mu, double mu0) const;
    int iterations() const { return iterations_; }

private:
    double albedo_;
    std::vector<double> mu_, weight_, h_;   // nodes, quadrature weights (in mu), H at the nodes
    int iterations_ = 0;
};

}  // namespace vpm
