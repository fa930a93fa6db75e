#pragma once
// Kernels of the kNN density estimate. A kernel is one profile function and one line
// in the registry table kKernels (kernels.cpp); the config's photons.kernel, the sweep axis
// `kernel` and the kernel study read that registry. The estimator (photons.estimator:
// classic keeps the k-th photon, corrected discards it, mse_optimal shrinks corrected) is
// chosen independently; Estimator::with_kernel combines the two.
//
// With bandwidth r = r_k (or R for a fixed-radius estimate) and t_i = r_i / r in [0, 1]:
//
//     S = sum_i w_i K(t_i) / (N_d r^d),   N_d = V_d(1) * n_d,
//
// V_d(1) the unit ball volume (pi, 4/3 pi) and n_d the kernel's normalisation relative to the
// ball, from the registry (closed form). A kernel is properly normalised when n_d equals the
// mean of K over the unit ball, M_d = d int_0^1 K(t) t^{d-1} dt; the constant kernel has
// n_d = M_d = 1 and gives the classic / corrected estimators exactly (bit for bit: the constant
// kernel takes the old code path). Profiles are written in u = t^2 (no square root except the
// cone's).
//
//   | kernel          | K(t)                                          | n_2          | n_3          |
//   |-----------------|-----------------------------------------------|--------------|--------------|
//   | constant        | 1                                             | 1            | 1            |
//   | cone            | 1 - s t, slope s in (0, 1] (Jensen's k = 1/s) | 1 - 2s/3     | 1 - 3s/4     |
//   | epanechnikov    | 1 - t^2                                       | 1/2          | 2/5          |
//   | silverman       | (1 - t^2)^2 (biweight)                        | 1/3          | 8/35         |
//
// In 1D (photon beams: the interval [-r, r], V_1(1) = 2) n_1 = int_0^1 K dt: constant 1, cone
// 1 - s/2, epanechnikov 2/3, silverman 8/15, gaussian_jensen 1 (the convention), gaussian
// a[1 - (1 - sqrt(pi/(2b)) erf(sqrt(b/2))) / (1 - e^{-b})] = 0.65196.
//   | gaussian_jensen | a [1 - (1 - e^{-b t^2/2}) / (1 - e^{-b})],    | 1 (Jensen's: | 1 (the same  |
//   |                 | a = 0.918, b = 1.953 (Jensen, Pavicic)        | / pi r^2)    | convention)  |
//   | gaussian        | the same profile                              | M_2 (exact)  | M_3 (exact)  |
//
// Gaussian means (exact): M_2 = a[1 - (1 - (2/b)(1 - e^{-b/2})) / (1 - e^{-b})] = 0.53115 (so
// Jensen's normalisation underestimates by 46.9% in 2D), M_3 = a[1 - (1 - 3J) / (1 - e^{-b})]
// with J = int_0^1 t^2 e^{-c t^2} dt = sqrt(pi) erf(sqrt c) / (4 c^{3/2}) - e^{-c} / (2c),
// c = b/2 (M_3 = 0.46394: -53.6% in 3D). The corrected Gaussian is Jensen's with
// a' = a / M_d (1.7283 in 2D, 1.9787 in 3D). K(1) = a e^{-b/2} / (1 + e^{-b/2}) = 0.25115.
#include <string>
#include <vector>

namespace vpm {

struct KernelEntry {
    const char* name;
    const char* formula;                              // one line for tables and --help
    double (*profile)(double u, double parameter);    // K as a function of u = t^2 in [0, 1]
    double (*normalisation)(int dim, double parameter);   // n_d (closed form), dim 1, 2 or 3
    const char* parameter = nullptr;                  // name of the parameter (config key
                                                      // photons.<kernel>_<parameter>), or null
    double default_parameter = 0.0;
    double parameter_lo = 0.0, parameter_hi = 0.0;    // allowed range (lo exclusive, hi inclusive)
};

// Moments of the relative kernel weight omega(t) = K(t) / n_d over the unit ball (t^d ~ U(0,1)),
// by quadrature of the profile (independent of the closed-form normalisation):
//   m1 = E[omega] (1 for a properly normalised kernel), m2 = E[omega^2], k1 = omega(1) (the
//   weight of the k-th photon, which lies on the sphere). The constant kernel: all exactly 1.
struct KernelMoments {
    double m1 = 1.0, m2 = 1.0, k1 = 1.0;
    bool constant = true;
    // E[omega^2]/E[omega]^2 >= 1: the kernel's variance factor (relative variance q/(k-2) for the
    // corrected estimate with unit weights, against 1/(k-2) for the constant kernel).
    double variance_factor() const { return constant ? 1.0 : m2 / (m1 * m1); }
};

// A typed handle on one registry entry with its parameter: cheap to copy and compare.
class Kernel {
public:
    static Kernel constant();
    // Throws vpm::Error naming the allowed values (or the parameter's range).
    static Kernel named(const std::string& name);
    static Kernel named(const std::string& name, double parameter);
    // Every registered kernel with its default parameter, in registry order.
    static const std::vector<Kernel>& all();
    static std::vector<std::string> names();

    const KernelEntry& entry() const { return *entry_; }
    const char* name() const { return entry_->name; }
    double parameter() const { return parameter_; }
    bool has_parameter() const { return entry_->parameter != nullptr; }
    // "cone(slope=0.5)" for a parameterised kernel, else the name.
    std::string label() const;
    bool is_constant() const { return constant_; }
    // omega(u) = K(sqrt u) / n_d: the weight of a neighbour at squared relative distance u, so that
    // S = sum w_i omega(u_i) / V_d(r). dim must be 1, 2 or 3.
    // dim 1: the 1D normalisation of photon beams (n_1 = int_0^1 K(t) dt, so that
    // int_{-r}^{r} omega(u^2/r^2) du / (2 r) = 1; render/photon_map/gathers/photon_beams_gather.h).
    double weight(double u, int dim) const { return entry_->profile(u, parameter_) * inv_norm_[dim - 1]; }
    // The closed-form n_d of the registry, and the mean of K over the unit ball M_d by quadrature.
    double normalisation(int dim) const;
    double profile_mean(int dim) const;
    const KernelMoments& moments(int dim) const { return moments_[dim - 1]; }

    bool operator==(const Kernel& o) const { return entry_ == o.entry_ && parameter_ == o.parameter_; }
    bool operator!=(const Kernel& o) const { return !(*this == o); }

private:
    Kernel(const KernelEntry* e, double parameter);
    const KernelEntry* entry_;
    double parameter_;
    bool constant_;
    double inv_norm_[3];      // dims 1, 2, 3
    KernelMoments moments_[3];
};

// d int_0^1 f(t) t^{d-1} dt by composite Simpson (4096 intervals): the mean of f(|x|) over the
// unit ball. f is smooth on [0, 1] for every registered kernel.
double ball_mean(int dim, double (*f)(double t, const void* ctx), const void* ctx);

}  // namespace vpm
