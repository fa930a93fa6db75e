#include "analysis/study/chandrasekhar_h.h"

#include <cmath>
#include <string>

#include <Eigen/Dense>

#include "core/error.h"
#include "core/math.h"

namespace vpm {

namespace {

// Gauss-Legendre nodes and weights on [0, 1] (Newton on P_n from the Chebyshev guess).
void gauss_legendre(int n, std::vector<double>& x, std::vector<double>& w) {
    x.assign(size_t(n), 0.0);
    w.assign(size_t(n), 0.0);
    for (int i = 0; i < n; ++i) {
        double z = std::cos(kPi * (i + 0.75) / (n + 0.5));
        double dp = 0.0;
        for (int it = 0; it < 100; ++it) {
            double p0 = 1.0, p1 = z;   // P_0, P_1
            for (int j = 2; j <= n; ++j) {
                const double p2 = ((2.0 * j - 1.0) * z * p1 - (j - 1.0) * p0) / j;
                p0 = p1;
                p1 = p2;
            }
            dp = n * (z * p1 - p0) / (z * z - 1.0);
            const double dz = p1 / dp;
            z -= dz;
            if (std::abs(dz) < 1e-16) break;
        }
        x[size_t(i)] = 0.5 * (1.0 - z);
        w[size_t(i)] = 1.0 / ((1.0 - z * z) * dp * dp);   // 2 / ((1 - z^2) P'^2), halved for [0, 1]
    }
}

}  // namespace

ChandrasekharH::ChandrasekharH(double albedo, int nodes) : albedo_(albedo) {
    if (!(albedo >= 0.0 && albedo <= 1.0)) throw Error("ChandrasekharH: albedo " + std::to_string(albedo) + " (allowed: 0 to 1)");
    if (nodes < 8) throw Error("ChandrasekharH: " + std::to_string(nodes) + " nodes (allowed: 8 or more)");
    std::vector<double> t, wt;
    gauss_legendre(nodes, t, wt);
    mu_.resize(t.size());
    weight_.resize(t.size());
    for (size_t j = 0; j < t.size(); ++j) {   // mu = t^2, dmu = 2 t dt
        mu_[j] = t[j] * t[j];
        weight_[j] = 2.0 * t[j] * wt[j];
    }
    // Newton's method on F_i(h) = h_i (sqrt(1 - a) + a/2 sum_j K_ij h_j) - 1, K_ij = w_j mu_j / (mu_i + mu_j):
    // the plain fixed-point iteration converges only sublinearly at a = 1.
    const size_t n = mu_.size();
    Eigen::MatrixXd k(n, n);
    for (size_t i = 0; i < n; ++i)
        for (size_t j = 0; j < n; ++j) k(Eigen::Index(i), Eigen::Index(j)) = weight_[j] * mu_[j] / (mu_[i] + mu_[j]);
    const double root = std::sqrt(1.0 - albedo_);
    Eigen::VectorXd h = Eigen::VectorXd::Ones(Eigen::Index(n));
    for (iterations_ = 1; iterations_ <= 100; ++iterations_) {
        const Eigen::VectorXd d = (root + 0.5 * albedo_ * (k * h).array()).matrix();
        const Eigen::VectorXd f = (h.array() * d.array() - 1.0).matrix();
        Eigen::MatrixXd jac = (0.5 * albedo_) * (h.asDiagonal() * k);
        jac.diagonal() += d;
        const Eigen::VectorXd step = jac.partialPivLu().solve(f);
        h -= step;
        if (step.cwiseAbs().maxCoeff() < 1e-14) {
            h_.assign(h.data(), h.data() + n);
            return;
        }
    }
    throw Error("ChandrasekharH: no convergence at albedo " + std::to_string(albedo_));
}

double ChandrasekharH::operator()(double mu) const {
    if (!(mu >= 0.0 && mu <= 1.0)) throw Error("ChandrasekharH: mu " + std::to_string(mu) + " (allowed: 0 to 1)");
    if (mu == 0.0) return 1.0;
    double s = 0.0;
    for (size_t j = 0; j < mu_.size(); ++j) s += weight_[j] * mu_[j] * h_[j] / (mu + mu_[j]);
    return 1.0 / (std::sqrt(1.0 - albedo_) + 0.5 * albedo_ * s);
}

double ChandrasekharH::moment(int n) const {
    double s = 0.0;
    for (size_t j = 0; j < mu_.size(); ++j) s += weight_[j] * h_[j] * (n == 0 ? 1.0 : mu_[j]);
    return s;
}

double ChandrasekharH::single_scattering(double mu, double mu0) const {
    return albedo_ / (4.0 * kPi) * mu0 / (mu + mu0);
}

double ChandrasekharH::reflected(double mu, double mu0) const {
    return single_scattering(mu, mu0) * (*this)(mu) * (*this)(mu0);
}

}  // namespace vpm
