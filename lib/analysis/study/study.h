#pragma once
// analysis/: what researchers measure with vpm, on top of render/: this study, sweeps (sweep_plan.h,
// sweep.h) with their error metrics and tables, and the stress matrix (stress.h). Analyses consume
// typed results (RunStats), never a run's JSON read back.
//
// The estimator study: Monte Carlo of the classic, corrected (k-1) and MSE-optimal
// (k-2) kNN density estimators against exact order-statistics theory.
//
// Every scenario draws n points (photons) with a known density at the query point, normalised so
// that the true power density there is 1; each estimate is therefore directly the relative
// estimate e, and the study reports mean(e) - 1 (+- standard error), var(e) and mean((e-1)^2).
// The estimates come from vpm::estimate_density (lib/photon/estimate/estimators.h), the same code the
// renderer uses; the k nearest of the n points are found with nth_element (exact).
//
// Scenarios (theory_source says where the theory column comes from):
//   uniform    n points uniform in the unit disc / ball, query at the centre (the seed's study).
//              Exact finite-n theory: U = V(r_k)/|R| ~ Beta(k, n-k+1), E[1/U] = n/(k-1),
//              E[1/U^2] = n(n-1)/((k-1)(k-2)); relative variance = limit * (n-k+1)/n.
//   gradient   density proportional to 1 + a x_1 in the unit disc / ball, query at the centre.
//              The linear part integrates to 0 over any centred ball, so r_k has exactly the
//              uniform distribution: no proximity bias, theory identical to uniform ("exact").
//   gaussian   isotropic Gaussian (sigma 1) centred on the query: proximity bias (ball mean <
//              peak) competes with the k/(k-1) overestimation. Theory by quadrature over
//              U ~ Beta(k, n-k+1) with r_k = F^{-1}(U), F the chi CDF ("quadrature").
//   boundary   uniform in the unit disc / ball, query at distance boundary_distance from the
//              centre: once r_k exceeds the distance to the edge the ball sticks out (boundary
//              bias). Theory by quadrature with F = lens volume / |R|. Truth: the interior
//              density (1).
//   weighted   uniform as above, each photon with power w ~ Exp(1) (E[w] = 1, c_w = E[w^2]/E[w]^2
//              = 2): corrected relative variance (c_w + k - 2)(n-1)/(n(k-2)) - 1 -> c_w/(k-2).
//   photon_map (3D) uniform photons in the unit cube stored in the real PhotonMap (compressed
//              records, nanoflann kd-tree), queried with estimate_in_scattering (isotropic
//              phase) at well-separated interior points. Exact uniform theory with n = map size.
//   kernels    uniform as above, every estimator with every study kernel (StudyOptions::kernels:
//              the registry's kernels and the cone at slope 0.5, photon/estimate/kernels.h): the follow-up
//              (Garcia, Urena & Sbert, TVCG 2014). Exact finite-n theory from the kernel's moments
//              (EstimatorEntry::uniform_theory); rows are labelled "classic/epanechnikov".
//   photon_pass (3D) photons from the renderer's photon pass in a volume furnace (see
//              study_photon_pass_map), in the real PhotonMap. Photons left by one random walk are
//              correlated, so the Poisson theory is a reference, not an identity: the difference
//              is the finding.
//   beam       the sample-point estimate behind photons.gather = "beam" (analysis/study/sample_point_trial.h):
//              n points uniform in the unit torus, each with the radius of its k-th nearest other
//              point; 3D rows: the point estimate at the centre (3D kernel), 2D rows: the beam
//              estimate along a segment of length 1/2 (2D kernel over each point's disc), every
//              kernel of StudyOptions::kernels (the row's estimator is "sample_point/<kernel>").
//              Theory: the mean M_d / n_d exactly (1 for normalised kernels: no k-1 factor), the
//              variance to first order (docs/beam_estimate.md; theory_source "exact_mean").
//              Needs n >= 3 k (radii below half the torus).
//   stratified n points in the unit square / cube (periodic) from each point set of
//              study_point_sets(): independent, the renderer's samplers "stratified" and "sobol"
//              (core/sampling/sampler.h), a d-dimensional jittered grid and a randomly shifted lattice (the
//              regular limit); query uniform in the torus, so each trial averages over where the
//              ball sits on the structure. Rows "stratified/<set>". Every point is uniform, the
//              density n exactly; only the count's variance changes. Theory: the exact Poisson
//              (binomial) theory for independent, else the first-order law of docs/stratified_sampling.md
//              from the count's Fano factor F(k) = Var N / k in a ball of mean k, measured in the same
//              trials (theory_source "fano"): classic bias (1 + F) / 2k, corrected -(1 - F) / 2k.
//              Needs n >= 4 k (radii below half the torus). Not in the default list.
//   photon_beams the balloon photon-beams estimate (render/photon_map/gathers/photon_beams_gather.h) on a
//              uniform isotropic Poisson field of beams (analysis/study/photon_beam_trial.h), classic
//              and corrected with every kernel of StudyOptions::kernels in 1D normalisation;
//              rows dim 1, estimator "balloon_<numerator>[/<kernel>]". Exact theory
//              (docs/photon_beams.md): classic E = m1 + k1/(k-1) (k/(k-1) for the constant
//              kernel), corrected m1, variances with the angular factor pi^2/8. k <= 256; not
//              among the defaults (ask for it).
//   walks      (3D) photons that are not independent: random walks in an infinite uniform medium
//              (analysis/study/walk_trial.h) at every StudyOptions::walk_media entry (albedo 0.3, 0.5, 0.9,
//              0.99, g 0 and 0.8), rows "walks/a<albedo>/g<g>": the photon-neighbour classic and
//              corrected, the walk-neighbour walk_classic and walk_corrected
//              (photon/estimate/walk_estimate.h) and leave_group_out. Theory: walk_corrected and
//              leave_group_out exact (0, "exact_mean"); walk_classic exact for many walks
//              ("quadrature": from the walks entering a ball, c(R)); classic and corrected first
//              order in the clustering ("first_order", docs/walk_correlation.md), from the
//              sibling-pair distances of independent walks. Not among the defaults (ask for it).
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "analysis/study/walk_trial.h"
#include "photon/estimate/estimators.h"

namespace vpm {

enum class StudyScenario { uniform, gradient, gaussian, boundary, weighted, photon_map, photon_pass, kernels, beam, stratified, photon_beams, walks };
const char* scenario_name(StudyScenario s);
StudyScenario parse_scenario(const std::string& name);   // throws vpm::Error listing allowed names
std::vector<StudyScenario> default_scenarios();           // all but beam (O(n^2) per trial), stratified, photon_beams and walks: ask for them

// The stratified scenario's point sets, in row order.
const std::vector<std::string>& study_point_sets();

// The kernels scenario's kernels: every registered kernel (default parameters), then the cone at
// slope 0.5 (Jensen's k = 2, not consistent with the k-th photon kept).
std::vector<Kernel> default_study_kernels();

struct StudyOptions {
    std::vector<int> dims = {2, 3};
    std::vector<size_t> ks;            // empty: default_k_list()
    size_t trials = 10000;             // per scenario and dimension
    size_t n = 1000;                   // points per trial (must exceed the largest k)
    uint64_t seed = 20130619;
    std::vector<StudyScenario> scenarios = default_scenarios();
    double gradient_slope = 0.9;       // density 1 + a x_1, |a| < 1
    double boundary_distance = 0.9;    // query distance from the centre, in [0, 1]
    size_t photon_map_size = 100000;   // photons per map (photon_map), emitted per map (photon_pass)
    size_t photon_map_queries = 0;     // estimates in the photon_map scenario (0: trials / 4)
    std::vector<Kernel> kernels = default_study_kernels();   // the kernels scenario's kernels
    // The walks scenario (analysis/study/walk_trial.h): photon density per mfp^3, walks per trial (at
    // least 16 x the largest k), query points per trial, walks for the clustering theory, media.
    double walk_density = 40.0;
    size_t walks_per_trial = 4096;
    size_t walk_queries = 8;
    size_t walk_theory_walks = 4000;
    std::vector<WalkMedium> walk_media = study_walk_media();
};

// 2, 3, 4, 5, 6, 8, 10, 13, 16, 20, 25, 32, 40, 50, 64, 80, 100, 128, 160, 200, 256
std::vector<size_t> default_k_list();

struct StudyRow {
    std::string scenario;
    int dim = 3;
    size_t k = 0;
    Estimator estimator = Estimator::all().front();
    std::string method;                   // beam scenario: "sample_point/<kernel>" (then `estimator` is unused)
    size_t n = 0, trials = 0;
    double mean_error = 0, se_mean = 0;   // mean(e) - 1 and its standard error
    double rel_variance = 0;              // sample variance of e
    double rel_mse = 0, se_mse = 0;       // mean((e - 1)^2) and its standard error
    // theory (finite n where it differs from the limit); variance/MSE may be +inf (k = 2)
    bool has_theory = false;
    std::string theory_source;            // exact | quadrature | exact_mean (beam, walks) | fano | first_order (walks) | none
    double th_error = 0, th_variance = 0, th_mse = 0;
    double th_variance_limit = 0;         // n -> infinity (uniform-type scenarios), else = th_variance
};

// The row's estimator column: the method when set, else the estimator's label.
inline std::string study_row_label(const StudyRow& row) { return row.method.empty() ? row.estimator.label() : row.method; }

struct StudyResult {
    StudyOptions options;
    std::vector<StudyRow> rows;
    std::vector<std::string> notes;
    EstimatorStats stats;
    double seconds = 0;
    int threads = 1;
};

// Theory for the uniform-type scenarios: unit ball/disc, n points, i.i.d. weights with
// c_w = E[w^2]/E[w]^2 (1 for unit weights). Returns (relative error, variance, MSE); +inf
// variance/MSE at k = 2 for classic and corrected. n = 0 gives the n -> infinity limit.
using Theory = EstimatorTheory;
// With a kernel (Estimator::with_kernel) the theory depends on the dimension (2 or 3).
Theory uniform_theory(Estimator e, size_t k, size_t n, double c_w = 1.0, int dim = 3);

// Quadrature theory for unit weights: n points with mass fraction F(r) within distance r of the
// query (F increasing, F(r_max) = 1), phi_over_truth = photon power / true density.
Theory quadrature_theory(Estimator e, size_t k, size_t n, int dim,
                         const std::function<double(double)>& mass_fraction, double r_max,
                         double phi_over_truth);

// One photon map from an actual photon pass, for the photon_pass scenario: the renderer's photon
// tracer in the volume furnace of configs/uniform_furnace.toml (a non-absorbing homogeneous
// sphere under a constant environment). There the radiance is the environment's everywhere, so the collision
// power density is known exactly: truth = sigma_t * 4 pi L_env. Photons are stored at every
// collision; queries stay within `query_radius` of the centre, far from the boundary.
struct PhotonPassMap {
    std::vector<PhotonInput> photons;
    double truth = 0.0;           // collision power density (W / m^3)
    double query_radius = 0.0;
};
PhotonPassMap study_photon_pass_map(size_t emitted, uint64_t seed, uint64_t map_index);

// Sorts the options, fills the default k list and throws vpm::Error for what the study cannot run:
// k < 2, trials < 2, n <= the largest k, dims other than 2 and 3, and (check_study_memory) a run
// whose samples and per-thread points would not fit in 80% of physical memory, naming the options
// and the largest values that fit. run_estimator_study calls it first.
void validate_study_options(StudyOptions& options);
void check_study_memory(const StudyOptions& options);

// Runs the study; log receives progress lines (may be empty).
StudyResult run_estimator_study(const StudyOptions& options,
                                const std::function<void(const std::string&)>& log = {});

// Writers (the numbers are formatted here, in C++).
std::string study_csv(const StudyResult& r);
std::string study_markdown(const StudyResult& r);
std::string study_sidecar_json(const StudyResult& r);
// Compact table: one scenario and dimension, chosen k, "mean +- se (theory)" per estimator.
std::string study_summary_table(const StudyResult& r, const std::string& scenario, int dim,
                                const std::vector<size_t>& ks);
// The kernels scenario as the issue-15 table: kernel x {kept (classic), discarded (corrected)} x
// the chosen k, one dimension: theory, measured mean +- SE, relative MSE measured (theory).
std::string kernel_summary_table(const StudyResult& r, int dim, const std::vector<size_t>& ks);
// The follow-up's headline figures from the exact theory (no Monte Carlo): per kernel and
// dimension the limit bias m1 - 1 (fixed radius and k -> inf), the extra bias of the kept k-th
// photon k1/(k-1), and the variance factor q.
std::string kernel_headline_table(const std::vector<Kernel>& kernels);

}  // namespace vpm
