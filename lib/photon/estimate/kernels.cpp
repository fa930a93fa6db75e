#include "photon/estimate/kernels.h"

#include <cmath>
#include <cstdio>

#include "core/error.h"
#include "core/math.h"
#include "core/registry.h"

namespace vpm {

namespace {

// --- the profiles: K as a function of u = t^2 ---------------------------------------------------
double constant_profile(double, double) { return 1.0; }
double cone_profile(double u, double slope) { return 1.0 - slope * std::sqrt(u); }
double epanechnikov_profile(double u, double) { return 1.0 - u; }
double silverman_profile(double u, double) { return (1.0 - u) * (1.0 - u); }

// Jensen's Gaussian filter (Pavicic's constants).
constexpr double kGaussAlpha = 0.918, kGaussBeta = 1.953;
double gaussian_profile(double u, double) {
    return kGaussAlpha * (1.0 - -std::expm1(-0.5 * kGaussBeta * u) / -std::expm1(-kGaussBeta));
}

// --- their closed-form normalisations n_d (relative to the unit ball volume) -------------------
double one(int, double) { return 1.0; }
double cone_norm(int dim, double s) { return dim == 1 ? 1.0 - 0.5 * s : dim == 2 ? 1.0 - 2.0 * s / 3.0 : 1.0 - 0.75 * s; }
double epanechnikov_norm(int dim, double) { return dim == 1 ? 2.0 / 3.0 : dim == 2 ? 0.5 : 0.4; }
double silverman_norm(int dim, double) { return dim == 1 ? 8.0 / 15.0 : dim == 2 ? 1.0 / 3.0 : 8.0 / 35.0; }
// Exact mean of the Gaussian profile over the unit interval / disc / ball (see kernels.h).
double gaussian_norm(int dim, double) {
    const double b = kGaussBeta, c = 0.5 * b, den = -std::expm1(-b);
    if (dim == 1) return kGaussAlpha * (1.0 - (1.0 - std::sqrt(kPi / (2.0 * b)) * std::erf(std::sqrt(c))) / den);
    if (dim == 2) return kGaussAlpha * (1.0 - (1.0 - (2.0 / b) * -std::expm1(-c)) / den);
    const double j = std::sqrt(kPi) * std::erf(std::sqrt(c)) / (4.0 * c * std::sqrt(c)) - std::exp(-c) / (2.0 * c);
    return kGaussAlpha * (1.0 - (1.0 - 3.0 * j) / den);
}

// The registry: one line per kernel.
const KernelEntry kKernels[] = {
    {"constant", "K = 1 (the classic kNN estimate)", constant_profile, one},
    {"cone", "K = 1 - s t, normalised (1 - 2s/3) pi r^2 / (1 - 3s/4) 4/3 pi r^3; s = 1: triangular",
     cone_profile, cone_norm, "slope", 1.0, 0.0, 1.0},
    {"epanechnikov", "K = 1 - t^2, normalised pi r^2 / 2 / 8 pi r^3 / 15", epanechnikov_profile, epanechnikov_norm},
    {"silverman", "K = (1 - t^2)^2 (biweight), normalised pi r^2 / 3 / 32 pi r^3 / 105", silverman_profile,
     silverman_norm},
    {"gaussian_jensen", "K = 0.918 [1 - (1 - e^{-1.953 t^2/2}) / (1 - e^{-1.953})] over V(r) (Jensen's original)",
     gaussian_profile, one},
    {"gaussian", "Jensen's Gaussian profile over its exact integral (new normalisation)", gaussian_profile,
     gaussian_norm},
};

struct ProfilePower {
    const KernelEntry* e;
    double parameter, scale;
    int power;
};
double profile_power(double t, const void* ctx) {
    const auto* p = static_cast<const ProfilePower*>(ctx);
    const double v = p->e->profile(t * t, p->parameter) * p->scale;
    return p->power == 1 ? v : v * v;
}

}  // namespace

double ball_mean(int dim, double (*f)(double, const void*), const void* ctx) {
    const int M = 4096;
    const double h = 1.0 / M;
    double s = 0.0;
    for (int j = 0; j <= M; ++j) {
        const double t = h * j;
        const double wgt = (j == 0 || j == M) ? 1.0 : (j % 2 ? 4.0 : 2.0);
        s += wgt * f(t, ctx) * (dim == 1 ? 1.0 : dim == 2 ? t : t * t);
    }
    return double(dim) * s * h / 3.0;
}

Kernel::Kernel(const KernelEntry* e, double parameter)
    : entry_(e), parameter_(parameter), constant_(e == &kKernels[0]) {
    for (int i = 0; i < 3; ++i) {
        const int dim = 1 + i;
        const double n = e->normalisation(dim, parameter);
        if (!(n > 0.0) || !std::isfinite(n))
            throw Error(std::string("kernel ") + e->name + ": normalisation is not positive");
        inv_norm_[i] = 1.0 / n;
        KernelMoments& m = moments_[i];
        if (constant_) continue;   // all exactly 1
        m.constant = false;
        ProfilePower p1{e, parameter, inv_norm_[i], 1}, p2{e, parameter, inv_norm_[i], 2};
        m.m1 = ball_mean(dim, profile_power, &p1);
        m.m2 = ball_mean(dim, profile_power, &p2);
        m.k1 = weight(1.0, dim);
    }
}

Kernel Kernel::constant() { return all().front(); }

const std::vector<Kernel>& Kernel::all() {
    static const std::vector<Kernel> list = [] {
        std::vector<Kernel> l;
        for (const KernelEntry& e : kKernels) l.push_back(Kernel(&e, e.default_parameter));
        return l;
    }();
    return list;
}

std::vector<std::string> Kernel::names() { return registry_names(kKernels); }

Kernel Kernel::named(const std::string& name) {
    if (const KernelEntry* e = registry_find(kKernels, name)) return Kernel(e, e->default_parameter);
    throw Error("kernel: unknown value '" + name + "' (allowed: " + registry_list(names()) + ")");
}

Kernel Kernel::named(const std::string& name, double parameter) {
    const Kernel k = named(name);
    if (!k.has_parameter()) {
        if (parameter == k.parameter()) return k;
        throw Error("kernel " + name + " takes no parameter");
    }
    const KernelEntry& e = k.entry();
    if (!(parameter > e.parameter_lo && parameter <= e.parameter_hi)) {
        char buf[160];
        std::snprintf(buf, sizeof buf, "kernel %s: %s = %g is out of range (allowed: (%g, %g])", e.name, e.parameter,
                      parameter, e.parameter_lo, e.parameter_hi);
        throw Error(buf);
    }
    return Kernel(&e, parameter);
}

std::string Kernel::label() const {
    if (!has_parameter()) return name();
    char buf[96];
    std::snprintf(buf, sizeof buf, "%s(%s=%g)", name(), entry_->parameter, parameter_);
    return buf;
}

double Kernel::normalisation(int dim) const { return entry_->normalisation(dim, parameter_); }

double Kernel::profile_mean(int dim) const {
    ProfilePower p{entry_, parameter_, 1.0, 1};
    return ball_mean(dim, profile_power, &p);
}

}  // namespace vpm
