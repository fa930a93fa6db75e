#include "core/build_info.h"
#include "analysis/study/study.h"
#include "analysis/study/photon_beam_trial.h"


#include "analysis/study/sample_point_trial.h"

#include <tbb/combinable.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <sstream>
#include <unistd.h>

#include "core/henyey_greenstein.h"
#include "core/progress.h"
#include "photon/trace/photon_budget.h"
#include "core/sampling/rng.h"
#include "core/sampling/sampling.h"
#include "core/sampling/hashed_permutation.h"
#include "core/sampling/sampler.h"
#include "photon/map/photon_map.h"
#include "analysis/builtin_scenes.h"
#include "render/run/run_config.h"
#include "photon/trace/photon_tracer.h"

namespace vpm {

namespace {

struct Pt {
    double d2;
    double w;
};

double unit_volume(int dim) { return ball_volume(dim, 1.0); }

Vec3 uniform_point(int dim, Rng& rng) {
    if (dim == 2) {
        const Eigen::Vector2d p = sample_uniform_disc(rng.uniform(), rng.uniform());
        return Vec3(p.x(), p.y(), 0.0);
    }
    const double u1 = rng.uniform(), u2 = rng.uniform(), u3 = rng.uniform();
    return sample_uniform_ball(u1, u2, u3);
}

double std_normal(Rng& rng) {   // Box-Muller (one of the pair)
    const double u1 = 1.0 - rng.uniform(), u2 = rng.uniform();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * kPi * u2);
}

// Chi CDF with dim degrees of freedom (sigma 1): mass of the Gaussian within radius r.
double gaussian_mass(int dim, double r) {
    if (dim == 2) return -std::expm1(-0.5 * r * r);
    return std::erf(r / std::sqrt(2.0)) - std::sqrt(2.0 / kPi) * r * std::exp(-0.5 * r * r);
}

// Volume (area) of B(q, r) inside the unit ball (disc), |q| = d.
double lens_volume(int dim, double d, double r) {
    if (r <= 1.0 - d) return ball_volume(dim, r);
    if (r >= 1.0 + d) return ball_volume(dim, 1.0);
    if (d <= 0.0) return ball_volume(dim, std::min(r, 1.0));
    if (dim == 3) {
        const double R = 1.0;
        return kPi * (R + r - d) * (R + r - d) *
               (d * d + 2 * d * r - 3 * r * r + 2 * d * R + 6 * r * R - 3 * R * R) / (12.0 * d);
    }
    const double R = 1.0;
    const double a1 = std::clamp((d * d + r * r - R * R) / (2 * d * r), -1.0, 1.0);
    const double a2 = std::clamp((d * d + R * R - r * r) / (2 * d * R), -1.0, 1.0);
    const double s = (-d + r + R) * (d + r - R) * (d - r + R) * (d + r + R);
    return r * r * std::acos(a1) + R * R * std::acos(a2) - 0.5 * std::sqrt(std::max(0.0, s));
}

std::string fmt(double v) {
    if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
    if (std::isnan(v)) return "nan";
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.6g", v);
    return buf;
}
std::string fmt_fixed(double v, int prec) {
    if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*f", prec, v);
    return buf;
}

constexpr double kBeamStudyLength = 0.5;   // the beam scenario's segment (unit torus)

uint64_t stream_id(StudyScenario s, int dim, uint64_t i) {
    return (uint64_t(s) << 56) ^ (uint64_t(dim) << 48) ^ i;
}

// Per-trial generator: PCG streams that share a seed differ only in the increment and are
// related sequences, so the state seed is mixed with the stream as well.
Rng trial_rng(uint64_t seed, uint64_t stream) { return Rng(mix64(seed ^ mix64(stream + 0x632be59bd9b4e019ULL)), stream); }

// Reduces samples[t * stride + offset] over t into a row.
void reduce(const std::vector<double>& samples, size_t trials, size_t stride, size_t offset, StudyRow& row) {
    double sum = 0;
    for (size_t t = 0; t < trials; ++t) sum += samples[t * stride + offset];
    const double mean = sum / double(trials);
    double ss = 0, se_sum = 0;
    for (size_t t = 0; t < trials; ++t) {
        const double d = samples[t * stride + offset] - mean;
        ss += d * d;
        const double e = samples[t * stride + offset] - 1.0;
        se_sum += e * e;
    }
    const double var = trials > 1 ? ss / double(trials - 1) : 0.0;
    const double mse = se_sum / double(trials);
    double ss2 = 0;
    for (size_t t = 0; t < trials; ++t) {
        const double e = samples[t * stride + offset] - 1.0;
        ss2 += (e * e - mse) * (e * e - mse);
    }
    row.trials = trials;
    row.mean_error = mean - 1.0;
    row.se_mean = std::sqrt(var / double(trials));
    row.rel_variance = var;
    row.rel_mse = mse;
    row.se_mse = trials > 1 ? std::sqrt(ss2 / double(trials - 1) / double(trials)) : 0.0;
}

}  // namespace

const char* scenario_name(StudyScenario s) {
    switch (s) {
        case StudyScenario::uniform: return "uniform";
        case StudyScenario::gradient: return "gradient";
        case StudyScenario::gaussian: return "gaussian";
        case StudyScenario::boundary: return "boundary";
        case StudyScenario::weighted: return "weighted";
        case StudyScenario::photon_map: return "photon_map";
        case StudyScenario::photon_pass: return "photon_pass";
        case StudyScenario::kernels: return "kernels";
        case StudyScenario::beam: return "beam";
        case StudyScenario::stratified: return "stratified";
        case StudyScenario::photon_beams: return "photon_beams";
        case StudyScenario::walks: return "walks";
    }
    return "unknown";
}

StudyScenario parse_scenario(const std::string& name) {
    for (StudyScenario s : {StudyScenario::uniform, StudyScenario::gradient, StudyScenario::gaussian,
                            StudyScenario::boundary, StudyScenario::weighted, StudyScenario::photon_map,
                            StudyScenario::photon_pass, StudyScenario::kernels, StudyScenario::beam,
                            StudyScenario::stratified, StudyScenario::photon_beams, StudyScenario::walks})
        if (name == scenario_name(s)) return s;
    throw Error("study: unknown scenario '" + name +
                "' (allowed: uniform, gradient, gaussian, boundary, weighted, photon_map, photon_pass, kernels, beam, "
                "stratified, photon_beams, walks)");
}

std::vector<StudyScenario> default_scenarios() {
    return {StudyScenario::uniform, StudyScenario::gradient, StudyScenario::gaussian,
            StudyScenario::boundary, StudyScenario::weighted, StudyScenario::photon_map,
            StudyScenario::photon_pass, StudyScenario::kernels};
}

const std::vector<std::string>& study_point_sets() {
    static const std::vector<std::string> sets = {"independent", "stratified", "jittered", "sobol", "lattice"};
    return sets;
}

std::vector<Kernel> default_study_kernels() {
    std::vector<Kernel> k = Kernel::all();
    k.push_back(Kernel::named("cone", 0.5));
    return k;
}

std::vector<size_t> default_k_list() {
    return {2, 3, 4, 5, 6, 8, 10, 13, 16, 20, 25, 32, 40, 50, 64, 80, 100, 128, 160, 200, 256};
}

Theory uniform_theory(Estimator e, size_t k, size_t n, double c_w, int dim) {
    e.validate_k(k);
    if (!e.entry().uniform_theory) throw Error(std::string("study: estimator ") + e.name() + " has no uniform theory");
    return e.uniform_theory(k, n, c_w, dim);
}

Theory quadrature_theory(Estimator e, size_t k, size_t n, int dim,
                         const std::function<double(double)>& mass_fraction, double r_max,
                         double phi_over_truth) {
    e.validate_k(k);
    if (!e.entry().unit_weight_count || !e.kernel().is_constant())
        throw Error(std::string("study: estimator ") + e.name() + " has no quadrature theory (not a constant kernel)");
    const double kk = double(k), nn = double(n);
    const double mu = kk / (nn + 1.0);
    const double t_lo = std::log(mu) - (40.0 / std::max(1.0, kk - 2.0) + 12.0 / std::sqrt(kk));
    const double t_hi = std::min(0.0, std::log(mu) + std::log1p(12.0 / std::sqrt(kk) + 60.0 / kk));
    const int M = 4000;   // Simpson intervals (even)
    const double h = (t_hi - t_lo) / M;
    const double lbeta = std::lgamma(kk) + std::lgamma(nn - kk + 1.0) - std::lgamma(nn + 1.0);
    double i1 = 0, i2 = 0;
    for (int j = 0; j <= M; ++j) {
        const double t = t_lo + h * j;
        const double u = std::exp(t);
        if (u >= 1.0) continue;
        double lo = 0.0, hi = r_max;   // r = F^{-1}(u) by bisection
        for (int it = 0; it < 64; ++it) {
            const double mid = 0.5 * (lo + hi);
            (mass_fraction(mid) < u ? lo : hi) = mid;
        }
        const double v = ball_volume(dim, 0.5 * (lo + hi));
        const double lpdf = (kk - 1.0) * t + (nn - kk) * std::log1p(-u) - lbeta;
        const double wgt = (j == 0 || j == M) ? 1.0 : (j % 2 ? 4.0 : 2.0);
        const double g = std::exp(lpdf + t);   // pdf(u) du/dt
        i1 += wgt * g / v;
        i2 += wgt * g / (v * v);
    }
    i1 *= h / 3.0;
    i2 *= h / 3.0;
    const double c = e.entry().unit_weight_count(k);
    Theory th;
    const double mean = c * phi_over_truth * i1;
    th.error = mean - 1.0;
    if (k <= 2) {
        th.variance = th.mse = kInfinity;
    } else {
        const double m2 = c * c * phi_over_truth * phi_over_truth * i2;
        th.variance = m2 - mean * mean;
        th.mse = th.variance + th.error * th.error;
    }
    return th;
}

PhotonPassMap study_photon_pass_map(size_t emitted, uint64_t seed, uint64_t map_index) {
    // The same furnace the renderer's bias test uses; its truth follows from the scene itself.
    const RunConfig config =
        RunConfig::build(parse_config(builtin_uniform_furnace_toml(), "uniform_furnace.toml (built in)", "."));
    const Scene* scene = config.scene.get();
    const double sigma_t = scene->media.at(0)->sigma_t(Vec3::Zero());
    const double radiance = scene->escaped_radiance(Vec3::UnitZ())[1];
    PhotonTraceSettings ts;
    ts.count = emitted;
    ts.seed = seed;
    ts.stream_offset = map_index;
    ts.store_direct = true;
    ts.progress = false;
    // The renderer's memory guard: a map that cannot fit stops after its first chunk, not in bad_alloc.
    ts.on_chunk = make_photon_pass_guard(0.8 * double(physical_memory_bytes()), nullptr);
    PhotonPassMap out;
    try {
        out.photons = trace_photons(*scene, ts).photons;
    } catch (const Error& e) {
        throw Error("study: photon_pass scenario, --photon-map-size " + std::to_string(emitted) + " (its photons.count): " + e.what());
    }
    out.truth = sigma_t * 4.0 * kPi * radiance;
    // 2.5 from the sphere's boundary at radius 6: kNN balls stay well inside.
    out.query_radius = 0.5 * (scene->media[0]->bounds().hi - scene->media[0]->bounds().lo).x() - 2.5;
    return out;
}

namespace {

// photon_pass: maps from the furnace's photon pass; queries on a grid of points within the
// central region, spaced so that their kNN balls do not overlap. Samples are estimate / truth.
void run_photon_pass(const StudyOptions& opt, size_t kmax, size_t stride,
                     tbb::combinable<EstimatorStats>& stats, std::vector<double>& samples, size_t& trials,
                     size_t& n, const std::function<void(const std::string&)>& say) {
    const size_t nk = opt.ks.size(), ne = Estimator::all().size();
    // Each query needs its own ball of ~k_max photons from a fresh photon pass, so this scenario
    // costs ~trials x k_max traced collisions: it takes a tenth of the trials by default.
    const size_t want = opt.photon_map_queries ? opt.photon_map_queries : std::max<size_t>(2, opt.trials / 10);
    std::vector<std::vector<double>> per_map;
    size_t done = 0;
    for (uint64_t m = 0; done < want; ++m) {
        const PhotonPassMap pass = study_photon_pass_map(opt.photon_map_size, opt.seed, m + 1);
        const PhotonMap map(pass.photons);
        if (m == 0) n = map.size();
        // Density from the stored count is only used to space the queries.
        const double volume = 4.0 / 3.0 * kPi * 216.0;
        const double r_max = std::cbrt(3.0 * double(kmax) * volume / (4.0 * kPi * double(map.size())));
        const double spacing = 2.6 * r_max;
        const int g = std::max(1, int(2.0 * pass.query_radius / spacing));
        std::vector<Vec3> queries;
        for (int ix = 0; ix < g; ++ix)
            for (int iy = 0; iy < g; ++iy)
                for (int iz = 0; iz < g; ++iz) {
                    const Vec3 x = Vec3(ix, iy, iz) * spacing - Vec3::Constant(0.5 * (g - 1) * spacing);
                    if (x.norm() <= pass.query_radius && done + queries.size() < want) queries.push_back(x);
                }
        std::vector<double> local(queries.size() * stride, 0.0);
        tbb::parallel_for(size_t(0), queries.size(), [&](size_t q) {
            NeighbourList list;
            std::vector<double> w(kmax), d2(kmax);
            EstimatorStats& st = stats.local();
            const size_t found = map.knn(queries[q], kmax, kInfinity, list);
            for (size_t i = 0; i < found; ++i) {
                w[i] = list[i].power[1] / pass.truth;   // isotropic radiance: unweighted power
                d2[i] = list[i].d2;
            }
            for (size_t ki = 0; ki < nk; ++ki)
                for (size_t ei = 0; ei < ne; ++ei) {
                    const Estimator e = Estimator::all()[ei];
                    if (opt.ks[ki] < e.min_k()) continue;
                    local[q * stride + ki * ne + ei] =
                        estimate_density<double>(e, w.data(), d2.data(), found, found < kmax, opt.ks[ki], kInfinity, 3, &st)
                            .value;
                }
        });
        done += queries.size();
        per_map.push_back(std::move(local));
        say("study: photon_pass: map " + std::to_string(m + 1) + ", " + std::to_string(map.size()) + " photons stored, " +
            std::to_string(done) + "/" + std::to_string(want) + " queries");
    }
    samples.clear();
    for (const auto& l : per_map) samples.insert(samples.end(), l.begin(), l.end());
    trials = samples.size() / stride;
}

}  // namespace

namespace {

// One sample per (trial, k, estimator): samples[t * stride + ki * ne + ei], estimate / truth.
struct SampleGrid {
    size_t nk = 0, ne = 0;
    size_t stride() const { return nk * ne; }
    size_t at(size_t t, size_t ki, size_t ei) const { return t * stride() + ki * ne + ei; }
};

// Applies every estimator of the scenario at every k to one sorted neighbour list.
void estimate_all(const StudyOptions& opt, const SampleGrid& grid, const std::vector<Estimator>& ests, size_t t,
                  const double* w, const double* d2, size_t found, bool complete, int dim, EstimatorStats& st,
                  std::vector<double>& samples) {
    for (size_t ki = 0; ki < grid.nk; ++ki)
        for (size_t ei = 0; ei < grid.ne; ++ei) {
            const Estimator& e = ests[ei];
            if (opt.ks[ki] < e.min_k()) continue;
            samples[grid.at(t, ki, ei)] =
                estimate_density<double>(e, w, d2, found, complete, opt.ks[ki], kInfinity, dim, &st).value;
        }
}

}  // namespace

void validate_study_options(StudyOptions& opt) {
    if (opt.ks.empty()) opt.ks = default_k_list();
    std::sort(opt.ks.begin(), opt.ks.end());
    opt.ks.erase(std::unique(opt.ks.begin(), opt.ks.end()), opt.ks.end());
    if (opt.ks.front() < 2) throw Error("study: --k values must be >= 2 (got " + std::to_string(opt.ks.front()) + ")");
    if (opt.trials < 2) throw Error("study: --trials must be >= 2");
    const size_t kmax = opt.ks.back();
    if (opt.n <= kmax)
        throw Error("study: --n (" + std::to_string(opt.n) + ") must exceed the largest k (" + std::to_string(kmax) + ")");
    for (int d : opt.dims)
        if (d != 2 && d != 3) throw Error("study: --dims values must be 2 or 3 (got " + std::to_string(d) + ")");
    const bool map_scenario = std::find(opt.scenarios.begin(), opt.scenarios.end(), StudyScenario::photon_map) != opt.scenarios.end();
    if (map_scenario && opt.photon_map_size <= kmax)
        throw Error("study: --photon-map-size (" + std::to_string(opt.photon_map_size) + ") must exceed the largest k (" +
                    std::to_string(kmax) + ") for the photon_map scenario");
    if (!(std::abs(opt.gradient_slope) < 1.0)) throw Error("study: gradient slope must be in (-1, 1)");
    if (!(opt.boundary_distance >= 0.0 && opt.boundary_distance <= 1.0))
        throw Error("study: boundary distance must be in [0, 1]");
    const bool beam = std::find(opt.scenarios.begin(), opt.scenarios.end(), StudyScenario::beam) != opt.scenarios.end();
    const bool stratified = std::find(opt.scenarios.begin(), opt.scenarios.end(), StudyScenario::stratified) != opt.scenarios.end();
    if (stratified && opt.n < 4 * kmax)
        throw Error("study: --n (" + std::to_string(opt.n) + ") must be at least 4 x the largest k (" + std::to_string(4 * kmax) +
                    ") for the stratified scenario, so that every radius stays below half the unit torus");
    if (beam && opt.n < 3 * kmax)
        throw Error("study: --n (" + std::to_string(opt.n) + ") must be at least 3 x the largest k (" + std::to_string(3 * kmax) +
                    ") for the beam scenario, so that every radius stays below half the unit torus");
    const bool beams = std::find(opt.scenarios.begin(), opt.scenarios.end(), StudyScenario::photon_beams) != opt.scenarios.end();
    const bool walks = std::find(opt.scenarios.begin(), opt.scenarios.end(), StudyScenario::walks) != opt.scenarios.end();
    if (walks && opt.walks_per_trial < 16 * kmax)
        throw Error("study: walks per trial (" + std::to_string(opt.walks_per_trial) + ") must be at least 16 x the largest k (" +
                    std::to_string(16 * kmax) + ") for the walks scenario, so that every walk ball stays a ball of the periodic cube");
    if (walks && !(opt.walk_density > 0.0 && std::isfinite(opt.walk_density)))
        throw Error("study: walk density must be a positive number (got " + std::to_string(opt.walk_density) + ")");
    if (walks && (opt.walk_queries < 1 || opt.walk_theory_walks < 100 || opt.walk_media.empty()))
        throw Error("study: the walks scenario needs at least 1 query per trial, 100 theory walks and one medium");
    for (const WalkMedium& m : walks ? opt.walk_media : std::vector<WalkMedium>{})
        if (!(m.albedo > 0.0 && m.albedo < 1.0) || !(std::abs(m.g) < 1.0))
            throw Error("study: walks medium " + m.label() + ": albedo must be in (0, 1) and |g| < 1");
    if (beams && kmax > 256)
        throw Error("study: the photon_beams scenario takes k <= 256 (its field has 410 beams within the widest width "
                    "on average; got " + std::to_string(kmax) + ")");
    check_study_memory(opt);
}

void check_study_memory(const StudyOptions& opt) {
    // What a scenario holds at once (its samples are freed before the next one): one double per
    // (trial, k, estimator), and per worker thread n points and a k_max neighbour list (synthetic) or
    // a photon map of photon_map_size photons while its kd-tree is built (photon_map). The
    // photon_pass scenario's maps are guarded while they are traced (study_photon_pass_map).
    const double threads = double(tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism));
    const double limit = 0.8 * double(physical_memory_bytes());
    const double nk = double(opt.ks.size()), kmax = double(opt.ks.back());
    const double ne = double(Estimator::all().size());
    for (StudyScenario sc : opt.scenarios) {
        if (sc == StudyScenario::photon_pass || sc == StudyScenario::photon_beams || sc == StudyScenario::walks)
            continue;   // small per trial
        const double stride = nk * ne * (sc == StudyScenario::kernels ? double(opt.kernels.size()) : 1.0);
        double estimates = double(opt.trials), per_thread_points = double(opt.n), point_bytes = double(sizeof(Pt));
        const char* size_option = "--n";
        if (sc == StudyScenario::photon_map) {
            estimates = opt.photon_map_queries ? double(opt.photon_map_queries) : std::max(2.0, std::floor(double(opt.trials) / 4.0));
            per_thread_points = double(opt.photon_map_size);
            point_bytes = kPeakBytesPerStoredPhoton;
            size_option = "--photon-map-size";
        }
        const double sample_bytes = estimates * stride * 8.0;
        const double thread_bytes = threads * (per_thread_points * point_bytes + kmax * 16.0);
        if (sample_bytes + thread_bytes <= limit) continue;
        const double points_fit = std::floor(std::max(0.0, limit - sample_bytes) / (threads * point_bytes));
        const double trials_fit = std::floor(std::max(0.0, limit - thread_bytes) / (stride * 8.0));
        auto count = [](double v) {
            std::ostringstream c;
            if (v < 1e15) c << uint64_t(v);
            else c << std::setprecision(3) << v;
            return c.str();
        };
        std::ostringstream s;
        s.precision(3);
        s << "study: the " << scenario_name(sc) << " scenario needs about " << (sample_bytes + thread_bytes) / 1e9
          << " GB (" << count(estimates) << " trials x " << count(stride) << " k and estimator columns x 8 bytes = "
          << sample_bytes / 1e9 << " GB, plus " << count(threads) << " threads x " << size_option << " "
          << count(per_thread_points) << " x " << point_bytes << " bytes = " << thread_bytes / 1e9
          << " GB), more than 80% of this machine's " << double(physical_memory_bytes()) / 1e9 << " GB; ";
        if (points_fit > kmax) s << "with these trials " << size_option << " <= " << count(points_fit) << " fits";
        else s << "no " << size_option << " fits with these trials";
        if (sc == StudyScenario::photon_map) s << ", with this map size --trials <= " << count(4.0 * trials_fit + 3.0);
        else s << ", with this " << size_option << " --trials <= " << count(trials_fit);
        if (trials_fit < 2.0) s << " (none)";
        if (threads > 1) s << "; fewer --threads need less";
        throw Error(s.str());
    }
}

namespace {

// The synthetic scenarios: n points per trial from the scenario's density, query at the centre.
void run_synthetic(const StudyOptions& opt, StudyScenario sc, int dim, const SampleGrid& grid,
                   const std::vector<Estimator>& ests, tbb::combinable<EstimatorStats>& stats,
                   std::vector<double>& samples) {
    const size_t trials = opt.trials, n = opt.n, kmax = opt.ks.back();
    samples.assign(trials * grid.stride(), 0.0);
    const double vol = unit_volume(dim);
    double phi = vol / double(n);   // truth = 1
    if (sc == StudyScenario::gaussian) phi = std::pow(2.0 * kPi, 0.5 * dim) / double(n);
    const double a = opt.gradient_slope, bd = opt.boundary_distance;
    tbb::parallel_for(tbb::blocked_range<size_t>(0, trials), [&](const tbb::blocked_range<size_t>& range) {
        std::vector<Pt> pts(n);
        std::vector<double> w(kmax), d2(kmax);
        EstimatorStats& st = stats.local();
        for (size_t t = range.begin(); t != range.end(); ++t) {
            Rng rng = trial_rng(opt.seed, stream_id(sc, dim, t));
            for (size_t i = 0; i < n; ++i) {
                Vec3 p;
                double wt = 1.0;
                switch (sc) {
                    case StudyScenario::gradient:
                        do p = uniform_point(dim, rng);
                        while (rng.uniform() * (1.0 + std::abs(a)) >= 1.0 + a * p.x());
                        break;
                    case StudyScenario::gaussian:
                        p = Vec3(std_normal(rng), std_normal(rng), dim == 3 ? std_normal(rng) : 0.0);
                        break;
                    case StudyScenario::boundary:
                        p = uniform_point(dim, rng) - Vec3(bd, 0.0, 0.0);
                        break;
                    case StudyScenario::weighted:
                        p = uniform_point(dim, rng);
                        wt = -std::log1p(-rng.uniform());   // Exp(1)
                        break;
                    default: p = uniform_point(dim, rng); break;
                }
                pts[i] = {p.squaredNorm(), wt * phi};
            }
            auto by_d2 = [](const Pt& x, const Pt& y) { return x.d2 < y.d2; };
            if (kmax < n) std::nth_element(pts.begin(), pts.begin() + (kmax - 1), pts.end(), by_d2);
            std::sort(pts.begin(), pts.begin() + kmax, by_d2);
            for (size_t i = 0; i < kmax; ++i) {
                w[i] = pts[i].w;
                d2[i] = pts[i].d2;
            }
            estimate_all(opt, grid, ests, t, w.data(), d2.data(), kmax, kmax >= n, dim, st, samples);
        }
    });
}

// The stratified scenario, one point set: n points in the unit torus per trial, query uniform in
// it, every estimator at every k, and the count N_k in the ball of mean mass k around the query
// (counts[t * nk + ki]) for the Fano factor.
void run_point_set(const StudyOptions& opt, int dim, size_t set, const SampleGrid& grid,
                   const std::vector<Estimator>& ests, tbb::combinable<EstimatorStats>& stats,
                   std::vector<double>& samples, std::vector<double>& counts) {
    const size_t trials = opt.trials, n = opt.n, kmax = opt.ks.back(), nk = opt.ks.size();
    const size_t sorted = std::min(n, 2 * kmax + 64);   // enough for the count at every k (checked)
    samples.assign(trials * grid.stride(), 0.0);
    counts.assign(trials * nk, 0.0);
    const double phi = 1.0 / double(n);   // unit volume: truth = 1
    std::vector<double> mass_r2(nk);      // r^2 of the ball of mean mass k
    for (size_t ki = 0; ki < nk; ++ki)
        mass_r2[ki] = std::pow(double(opt.ks[ki]) / (double(n) * unit_volume(dim)), 2.0 / dim);
    const std::string& name = study_point_sets()[set];
    const SamplerKind kind = name == "sobol" ? SamplerKind::sobol : name == "stratified" ? SamplerKind::stratified
                                                                                         : SamplerKind::independent;
    // jittered and lattice: m^dim >= n cells, point i in cell pi(i) of a hashed permutation
    size_t m = size_t(std::floor(std::pow(double(n), 1.0 / dim)));
    while (size_t(std::pow(double(m), dim) + 0.5) < n) ++m;
    const uint32_t cells = uint32_t(std::pow(double(m), dim) + 0.5);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, trials), [&](const tbb::blocked_range<size_t>& range) {
        std::vector<Pt> pts(n);
        std::vector<double> w(kmax), d2(kmax), x(size_t(dim) * n);
        EstimatorStats& st = stats.local();
        for (size_t t = range.begin(); t != range.end(); ++t) {
            Rng rng = trial_rng(opt.seed, stream_id(StudyScenario::stratified, dim, (uint64_t(set) << 40) ^ t));
            const uint64_t key = mix64(opt.seed ^ mix64((uint64_t(set) << 40) ^ (uint64_t(dim) << 32) ^ t));
            if (name == "jittered" || name == "lattice") {
                double shift[3] = {rng.uniform(), rng.uniform(), rng.uniform()};
                for (size_t i = 0; i < n; ++i) {
                    uint32_t c = permutation_element(uint32_t(i), cells, key);
                    for (int j = 0; j < dim; ++j, c /= uint32_t(m)) {
                        const double u = name == "jittered" ? rng.uniform() : shift[j];
                        x[i * size_t(dim) + size_t(j)] = (double(c % uint32_t(m)) + u) / double(m);
                    }
                }
            } else {
                const PathSampler sampler(kind, key, n);
                for (size_t i = 0; i < n; ++i)
                    for (int j = 0; j < dim; ++j) x[i * size_t(dim) + size_t(j)] = sampler.sample(i, uint32_t(j));
            }
            double q[3];
            for (int j = 0; j < dim; ++j) q[j] = rng.uniform();
            for (size_t i = 0; i < n; ++i) {
                double r2 = 0.0;
                for (int j = 0; j < dim; ++j) {
                    double d = std::abs(x[i * size_t(dim) + size_t(j)] - q[j]);
                    d = std::min(d, 1.0 - d);   // the torus' nearest image
                    r2 += d * d;
                }
                pts[i] = {r2, phi};
            }
            auto by_d2 = [](const Pt& a, const Pt& b) { return a.d2 < b.d2; };
            if (sorted < n) std::nth_element(pts.begin(), pts.begin() + (sorted - 1), pts.end(), by_d2);
            std::sort(pts.begin(), pts.begin() + sorted, by_d2);
            if (pts[kmax - 1].d2 >= 0.25) throw Error("study: stratified: a k-th neighbour beyond half the torus (raise --n)");
            for (size_t i = 0; i < kmax; ++i) {
                w[i] = pts[i].w;
                d2[i] = pts[i].d2;
            }
            estimate_all(opt, grid, ests, t, w.data(), d2.data(), kmax, kmax >= n, dim, st, samples);
            for (size_t ki = 0; ki < nk; ++ki) {
                const size_t c = size_t(std::lower_bound(pts.begin(), pts.begin() + sorted, Pt{mass_r2[ki], 0.0}, by_d2) - pts.begin());
                if (c == sorted && sorted < n) throw Error("study: stratified: count beyond the sorted neighbours");
                counts[t * nk + ki] = double(c);
            }
        }
    });
}

// Real photon map: uniform photons in the unit cube, queries on a grid of well-separated
// interior points (balls never overlap or leave the cube). Returns the trials run.
size_t run_photon_map(const StudyOptions& opt, const SampleGrid& grid, tbb::combinable<EstimatorStats>& stats,
                      std::vector<double>& samples, const std::function<void(const std::string&)>& say) {
    const size_t n = opt.photon_map_size, kmax = opt.ks.back();
    if (n <= kmax) throw Error("study: photon map size must exceed the largest k");
    const double r_max = std::cbrt(3.0 * double(kmax) / (4.0 * kPi * double(n)));
    const double margin = 1.3 * r_max;
    const size_t g = std::max<size_t>(1, size_t((1.0 - 2.0 * margin) / (2.0 * margin)) + 1);
    const double spacing = g > 1 ? (1.0 - 2.0 * margin) / double(g - 1) : 0.0;
    const size_t per_map = g * g * g;
    const size_t want = opt.photon_map_queries ? opt.photon_map_queries : std::max<size_t>(2, opt.trials / 4);
    const size_t maps = (want + per_map - 1) / per_map;
    const size_t trials = maps * per_map;
    samples.assign(trials * grid.stride(), 0.0);
    const double phi = 1.0 / double(n);   // power density 1
    say("study: photon_map: " + std::to_string(maps) + " maps of " + std::to_string(n) + " photons, " +
        std::to_string(per_map) + " queries each");
    tbb::parallel_for(size_t(0), maps, [&](size_t m) {
        Rng rng = trial_rng(opt.seed, stream_id(StudyScenario::photon_map, 3, m));
        std::vector<PhotonInput> ph(n);
        for (auto& p : ph) {
            p.position = Vec3(rng.uniform(), rng.uniform(), rng.uniform());
            const double u1 = rng.uniform(), u2 = rng.uniform();
            p.direction = sample_uniform_sphere(u1, u2);
            p.power = Rgb::Constant(phi);
        }
        const PhotonMap map(ph);
        NeighbourList list;
        std::vector<double> w(kmax), d2(kmax);
        EstimatorStats& st = stats.local();
        const Vec3 wo = Vec3::UnitZ();
        for (size_t q = 0; q < per_map; ++q) {
            const size_t ix = q % g, iy = (q / g) % g, iz = q / (g * g);
            const Vec3 x = Vec3::Constant(margin) + spacing * Vec3(double(ix), double(iy), double(iz));
            const size_t found = map.knn(x, kmax, kInfinity, list);
            for (size_t i = 0; i < found; ++i) {
                // same weighting as estimate_in_scattering; isotropic phase 1/(4 pi)
                w[i] = 4.0 * kPi * hg_eval(list[i].direction.dot(wo), 0.0) * list[i].power[1];
                d2[i] = list[i].d2;
            }
            estimate_all(opt, grid, Estimator::all(), m * per_map + q, w.data(), d2.data(), found, found < kmax, 3, st,
                         samples);
        }
    });
    // Exactly the estimates asked for: the last map's grid of queries may hold more.
    samples.resize(std::min(trials, want) * grid.stride());
    return std::min(trials, want);
}

// beam: one torus cloud per trial gives the point (3D) and beam (2D) estimates of every k and kernel.
// Both are kept, so the second dimension reuses the first's trials. The trials go in 20 slices
// with a progress line after each (the defaults take tens of minutes); every trial has its own
// stream, so the slicing changes nothing.
void run_beam(const StudyOptions& opt, const SampleGrid& grid, std::vector<double>& point, std::vector<double>& beam,
              const std::function<void(const std::string&)>& say) {
    const size_t trials = opt.trials, slices = std::min<size_t>(20, std::max<size_t>(1, trials));
    point.assign(trials * grid.stride(), 0.0);
    beam.assign(trials * grid.stride(), 0.0);
    const Timer timer;
    for (size_t s = 0; s < slices; ++s) {
        const size_t begin = trials * s / slices, end = trials * (s + 1) / slices;
        tbb::parallel_for(tbb::blocked_range<size_t>(begin, end), [&](const tbb::blocked_range<size_t>& range) {
            for (size_t t = range.begin(); t != range.end(); ++t) {
                Rng rng = trial_rng(opt.seed, stream_id(StudyScenario::beam, 0, t));
                sample_point_trial(opt.n, kBeamStudyLength, opt.ks, opt.kernels, rng, &point[grid.at(t, 0, 0)], &beam[grid.at(t, 0, 0)]);
            }
        });
        if (slices > 1) {
            char buf[160];
            std::snprintf(buf, sizeof buf, "study: beam       %zu of %zu trials (n=%zu), %.1f s", end, trials, opt.n, timer.seconds());
            say(buf);
        }
    }
}

// photon_beams: one field of beams per trial gives the balloon estimates of every k, kernel and numerator.
void run_photon_beams(const StudyOptions& opt, std::vector<double>& samples, size_t stride) {
    samples.assign(opt.trials * stride, 0.0);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, opt.trials), [&](const tbb::blocked_range<size_t>& range) {
        for (size_t t = range.begin(); t != range.end(); ++t) {
            Rng rng = trial_rng(opt.seed, stream_id(StudyScenario::photon_beams, 1, t));
            photon_beam_trial(opt.ks, opt.kernels, rng, &samples[t * stride]);
        }
    });
}

// The theory column of one row, where the estimator's registry entry and the scenario give one.
void attach_theory(const StudyOptions& opt, StudyScenario sc, StudyRow& row) {
    const Estimator e = row.estimator;
    const size_t k = row.k, n = row.n;
    const int dim = row.dim;
    Theory th, lim;
    row.has_theory = false;
    row.theory_source = "none";
    switch (sc) {
        case StudyScenario::uniform:
        case StudyScenario::gradient:
        case StudyScenario::photon_map:
        case StudyScenario::photon_pass:
        case StudyScenario::weighted:
        case StudyScenario::kernels: {
            if (!e.entry().uniform_theory) return;
            const double c_w = sc == StudyScenario::weighted ? 2.0 : 1.0;   // Exp(1) weights: E[w^2]/E[w]^2 = 2
            th = uniform_theory(e, k, n, c_w, dim);
            lim = uniform_theory(e, k, 0, c_w, dim);
            row.theory_source = "exact";
            break;
        }
        case StudyScenario::gaussian:
            if (!e.entry().unit_weight_count) return;
            th = quadrature_theory(e, k, n, dim, [dim](double r) { return gaussian_mass(dim, r); }, 40.0,
                                   std::pow(2.0 * kPi, 0.5 * dim) / double(n));
            lim = th;
            row.theory_source = "quadrature";
            break;
        case StudyScenario::boundary: {
            if (!e.entry().unit_weight_count) return;
            const double bd = opt.boundary_distance, uv = unit_volume(dim);
            th = quadrature_theory(e, k, n, dim, [dim, bd, uv](double r) { return lens_volume(dim, bd, r) / uv; },
                                   1.0 + bd, uv / double(n));
            lim = th;
            row.theory_source = "quadrature";
            break;
        }
        default: return;
    }
    row.has_theory = true;
    row.th_error = th.error;
    row.th_variance = th.variance;
    row.th_mse = th.mse;
    row.th_variance_limit = lim.variance;
}

// The walks scenario: every medium, opt.trials independent trials each (analysis/study/walk_trial.h).
void run_walks(const StudyOptions& opt, StudyResult& res, const Timer& timer, const std::function<void(const std::string&)>& say) {
    const std::vector<std::string>& methods = walk_study_methods();
    const size_t nm = methods.size(), nk = opt.ks.size(), kmax = opt.ks.back();
    WalkTrialSettings st;
    st.density = opt.walk_density;
    st.walks = opt.walks_per_trial;
    st.queries = opt.walk_queries;
    for (size_t mi = 0; mi < opt.walk_media.size(); ++mi) {
        const WalkMedium& medium = opt.walk_media[mi];
        Timer t_sc;
        std::vector<double> samples(opt.trials * nk * nm, 0.0);
        std::vector<size_t> photons(opt.trials, 0);
        tbb::parallel_for(size_t(0), opt.trials, [&](size_t t) {
            Rng rng = trial_rng(opt.seed, stream_id(StudyScenario::walks, int(mi), t));
            std::vector<double> out;
            walk_trial(medium, st, opt.ks, rng, out, photons[t]);
            std::copy(out.begin(), out.end(), samples.begin() + long(t * nk * nm));
        });
        double photons_sum = 0.0;
        for (size_t p : photons) photons_sum += double(p);
        const size_t mean_photons = size_t(std::llround(photons_sum / double(opt.trials)));
        // The theory's radii reach past the Poisson support of k_max photons, and of k_max walks
        // entering with up to 16 photons each (walk_classic's theory; a larger c is an error there).
        const double r_max = 1.01 * std::cbrt(3.0 * 16.0 * (double(kmax) + 12.0 * std::sqrt(double(kmax)) + 30.0) /
                                              (4.0 * kPi * opt.walk_density));
        Rng theory_rng = trial_rng(opt.seed, stream_id(StudyScenario::walks, int(mi), uint64_t(1) << 40));
        Rng point_rng = trial_rng(opt.seed, stream_id(StudyScenario::walks, int(mi), (uint64_t(1) << 40) + 1));
        const WalkClustering clustering = walk_clustering(medium, opt.walk_theory_walks, theory_rng, r_max, point_rng);
        for (size_t ki = 0; ki < nk; ++ki)
            for (size_t m = 0; m < nm; ++m) {
                StudyRow row;
                row.estimator = Estimator::named(m == 0 || m == 2 ? "classic" : "corrected");
                row.method = methods[m];
                row.scenario = medium.label();
                row.dim = 3;
                row.k = opt.ks[ki];
                row.n = mean_photons;
                reduce(samples, opt.trials, nk * nm, ki * nm + m, row);
                row.has_theory = true;
                row.theory_source = m >= 3 ? "exact_mean" : m == 2 ? "quadrature" : "first_order";
                row.th_error = walk_theory_error(m, row.k, opt.walk_density, clustering);
                row.th_variance = row.th_mse = row.th_variance_limit = std::nan("");
                res.rows.push_back(row);
            }
        std::ostringstream note;
        note << medium.label() << ": photons per walk " << fmt_fixed(photons_sum / double(opt.trials * opt.walks_per_trial), 3)
             << " measured (1/(1 - albedo) = " << fmt_fixed(1.0 / (1.0 - medium.albedo), 3) << "); siblings per photon in a ball of k photons s(k):";
        for (size_t ki = 0; ki < nk; ++ki)
            note << (ki ? ", " : " ") << opt.ks[ki] << ": " << fmt_fixed(walk_siblings_at(opt.ks[ki], opt.walk_density, clustering), 4);
        note << "; photons inside it of a walk that enters it c(k):";
        for (size_t ki = 0; ki < nk; ++ki)
            note << (ki ? ", " : " ") << opt.ks[ki] << ": "
                 << fmt_fixed(walk_entering_photons_at(opt.ks[ki], opt.walk_density, clustering), 4);
        res.notes.push_back(note.str());
        char buf[240];
        std::snprintf(buf, sizeof buf, "study: %-18s 3D  %zu trials x %zu k  %zu walks, ~%zu photons  %.2f s (total %.1f s)",
                      medium.label().c_str(), opt.trials, nk, opt.walks_per_trial, mean_photons, t_sc.seconds(), timer.seconds());
        say(buf);
    }
}

// The 1D Poisson field of photon beams: balloon estimates against the exact theory.
void study_photon_beams(const StudyOptions& opt, StudyResult& res, const Timer& timer, const std::function<void(const std::string&)>& say) {
    const StudyScenario sc = StudyScenario::photon_beams;
    const size_t stride = opt.ks.size() * opt.kernels.size() * 2;
    std::vector<double> samples;
    Timer t_sc;
    run_photon_beams(opt, samples, stride);
    for (size_t ki = 0; ki < opt.ks.size(); ++ki)
        for (size_t kk = 0; kk < opt.kernels.size(); ++kk)
            for (int c = 0; c < 2; ++c) {
                const Kernel& kernel = opt.kernels[kk];
                StudyRow row;
                row.estimator = Estimator::named(c == 0 ? "classic" : "corrected").with_kernel(kernel);
                row.method = std::string("balloon_") + (c == 0 ? "classic" : "corrected") +
                             (kernel.is_constant() ? std::string() : "/" + kernel.label());
                row.k = opt.ks[ki];
                row.scenario = scenario_name(sc);
                row.dim = 1;
                row.n = 0;   // a Poisson field: no fixed count
                reduce(samples, opt.trials, stride, (ki * opt.kernels.size() + kk) * 2 + size_t(c), row);
                const BeamBalloonTheory th = photon_beam_balloon_theory(kernel, row.k, c == 0);
                row.has_theory = true;
                row.theory_source = "exact";
                row.th_error = th.mean - 1.0;
                row.th_variance = th.variance;
                row.th_mse = th.variance + row.th_error * row.th_error;
                row.th_variance_limit = th.variance;
                res.rows.push_back(row);
            }
    char buf[200];
    std::snprintf(buf, sizeof buf, "study: %-12s 1D  %zu trials x %zu k  Poisson field of beams  %.2f s (total %.1f s)",
                  scenario_name(sc), opt.trials, opt.ks.size(), t_sc.seconds(), timer.seconds());
    say(buf);
}

// Sample-point widths in 2D (beams) and 3D (points) against their exact means.
void study_beam(const StudyOptions& opt, StudyResult& res, const Timer& timer, const std::function<void(const std::string&)>& say) {
    const StudyScenario sc = StudyScenario::beam;
    const SampleGrid grid{opt.ks.size(), opt.kernels.size()};
    std::vector<double> point, beam;
    Timer t_sc;
    run_beam(opt, grid, point, beam, say);
    for (int dim : opt.dims)
        for (size_t ki = 0; ki < grid.nk; ++ki)
            for (size_t ei = 0; ei < grid.ne; ++ei) {
                const Kernel& kernel = opt.kernels[ei];
                StudyRow row;
                row.method = "sample_point/" + kernel.label();
                row.k = opt.ks[ki];
                row.scenario = scenario_name(sc);
                row.dim = dim;
                row.n = opt.n;
                reduce(dim == 3 ? point : beam, opt.trials, grid.stride(), grid.at(0, ki, ei), row);
                row.has_theory = true;
                row.theory_source = "exact_mean";
                row.th_error = sample_point_mean(kernel, dim) - 1.0;
                row.th_variance = dim == 3 ? sample_point_variance_3d(kernel, row.k)
                                           : sample_point_variance_beam(kernel, row.k, double(opt.n), kBeamStudyLength);
                row.th_mse = row.th_variance + row.th_error * row.th_error;
                row.th_variance_limit = row.th_variance;
                res.rows.push_back(row);
            }
    char buf[200];
    std::snprintf(buf, sizeof buf, "study: %-10s 2D+3D  %zu trials x %zu k  n=%zu  %.2f s (total %.1f s)",
                  scenario_name(sc), opt.trials, grid.nk, opt.n, t_sc.seconds(), timer.seconds());
    say(buf);
}

// Stratified point sets: each set's count Fano factor and the first-order theory it gives.
void study_stratified(const StudyOptions& opt, StudyResult& res, tbb::combinable<EstimatorStats>& stats, const Timer& timer,
                      const std::function<void(const std::string&)>& say) {
    const std::vector<Estimator>& ests = Estimator::all();
    const SampleGrid grid{opt.ks.size(), ests.size()};
    for (int dim : opt.dims)
        for (size_t set = 0; set < study_point_sets().size(); ++set) {
            Timer t_sc;
            std::vector<double> samples, counts;
            run_point_set(opt, dim, set, grid, ests, stats, samples, counts);
            const std::string label = "stratified/" + study_point_sets()[set];
            std::ostringstream fano_note;
            fano_note << label << " " << dim << "D: count Fano factor F(k) = Var N / k";
            for (size_t ki = 0; ki < grid.nk; ++ki) {
                const size_t k = opt.ks[ki];
                double sum = 0, sum2 = 0;
                for (size_t t = 0; t < opt.trials; ++t) {
                    sum += counts[t * grid.nk + ki];
                    sum2 += counts[t * grid.nk + ki] * counts[t * grid.nk + ki];
                }
                const double mean = sum / double(opt.trials);
                const double fano = (sum2 - sum * mean) / double(opt.trials - 1) / double(k);
                fano_note << (ki ? ", " : " ") << k << ": " << fmt_fixed(fano, 3);
                for (size_t ei = 0; ei < grid.ne; ++ei) {
                    StudyRow row;
                    row.estimator = ests[ei];
                    row.k = k;
                    if (row.k < row.estimator.min_k()) continue;
                    row.scenario = label;
                    row.dim = dim;
                    row.n = opt.n;
                    reduce(samples, opt.trials, grid.stride(), grid.at(0, ki, ei), row);
                    if (set == 0) {
                        attach_theory(opt, StudyScenario::uniform, row);
                    } else if (row.estimator.entry().unit_weight_count) {
                        // First order in the count's fluctuation (docs/stratified_sampling.md):
                        // E[1/X] = (1 + (1 + F) / 2k) / k, Var[X] = F k for X = n V(r_k).
                        const double c = row.estimator.entry().unit_weight_count(k) / double(k);
                        row.has_theory = true;
                        row.theory_source = "fano";
                        row.th_error = c * (1.0 + (1.0 + fano) / (2.0 * double(k))) - 1.0;
                        row.th_variance = c * c * fano / double(k);
                        row.th_mse = row.th_variance + row.th_error * row.th_error;
                        row.th_variance_limit = row.th_variance;
                    }
                    res.rows.push_back(row);
                }
            }
            res.notes.push_back(fano_note.str());
            char buf[200];
            std::snprintf(buf, sizeof buf, "study: %-22s %dD  %zu trials x %zu k  n=%zu  %.2f s (total %.1f s)",
                          label.c_str(), dim, opt.trials, grid.nk, opt.n, t_sc.seconds(), timer.seconds());
            say(buf);
        }
}

// The uniform, kernel, synthetic and real-map scenarios: one row per k and estimator.
void study_estimates(const StudyOptions& opt, StudyScenario sc, const std::vector<Estimator>& kernel_ests, StudyResult& res,
                     tbb::combinable<EstimatorStats>& stats, const Timer& timer, const std::function<void(const std::string&)>& say) {
    const std::vector<Estimator>& ests = sc == StudyScenario::kernels ? kernel_ests : Estimator::all();
    const SampleGrid grid{opt.ks.size(), ests.size()};
    for (int dim : opt.dims) {
        const bool real_map = sc == StudyScenario::photon_map || sc == StudyScenario::photon_pass;
        if (real_map && dim != 3) continue;
        Timer t_sc;
        size_t trials = opt.trials;
        size_t n = opt.n;
        std::vector<double> samples;
        if (!real_map) {
            run_synthetic(opt, sc, dim, grid, ests, stats, samples);
        } else if (sc == StudyScenario::photon_pass) {
            run_photon_pass(opt, opt.ks.back(), grid.stride(), stats, samples, trials, n, say);
        } else {
            n = opt.photon_map_size;
            trials = run_photon_map(opt, grid, stats, samples, say);
        }
        if (real_map)   // they take a share of --trials: say so
            res.notes.push_back(std::string(scenario_name(sc)) + ": " + std::to_string(trials) + " estimates per k (" +
                                (opt.photon_map_queries ? std::string("StudyOptions::photon_map_queries")
                                 : sc == StudyScenario::photon_map ? "--trials / 4" : "--trials / 10") +
                                ", at least 2: each estimate needs its own region of a photon map)");
        for (size_t ki = 0; ki < grid.nk; ++ki)
            for (size_t ei = 0; ei < grid.ne; ++ei) {
                StudyRow row;
                row.estimator = ests[ei];
                row.k = opt.ks[ki];
                if (row.k < row.estimator.min_k()) continue;
                row.scenario = scenario_name(sc);
                row.dim = dim;
                row.n = n;
                reduce(samples, trials, grid.stride(), grid.at(0, ki, ei), row);
                attach_theory(opt, sc, row);
                res.rows.push_back(row);
            }
        char buf[200];
        std::snprintf(buf, sizeof buf, "study: %-10s %dD  %zu trials x %zu k  n=%zu  %.2f s (total %.1f s)",
                      scenario_name(sc), dim, trials, grid.nk, n, t_sc.seconds(), timer.seconds());
        say(buf);
    }
}

}  // namespace

StudyResult run_estimator_study(const StudyOptions& opt_in, const std::function<void(const std::string&)>& log) {
    Timer timer;
    StudyResult res;
    res.options = opt_in;
    StudyOptions& opt = res.options;
    validate_study_options(opt);
    auto say = [&](const std::string& s) {
        if (log) log(s);
    };
    // The limit --threads set (tbb::global_control), not the machine's core count.
    res.threads = int(tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism));
    const bool balloon = std::any_of(opt.scenarios.begin(), opt.scenarios.end(), [](StudyScenario sc) { return sc != StudyScenario::beam; });
    for (size_t k : balloon ? opt.ks : std::vector<size_t>{})
        for (const Estimator& e : Estimator::all())
            if (const std::string w = e.warning(k); !w.empty()) res.notes.push_back("k = " + std::to_string(k) + ": " + w);
    std::vector<Estimator> kernel_ests;   // the kernels scenario: kernel-major, registry order inside
    for (const Kernel& k : opt.kernels)
        for (const Estimator& e : Estimator::all()) kernel_ests.push_back(e.with_kernel(k));
    tbb::combinable<EstimatorStats> stats;

    for (StudyScenario sc : opt.scenarios) {
        if (sc == StudyScenario::walks) run_walks(opt, res, timer, say);
        else if (sc == StudyScenario::photon_beams) study_photon_beams(opt, res, timer, say);
        else if (sc == StudyScenario::beam) study_beam(opt, res, timer, say);
        else if (sc == StudyScenario::stratified) study_stratified(opt, res, stats, timer, say);
        else study_estimates(opt, sc, kernel_ests, res, stats, timer, say);
    }
    stats.combine_each([&](const EstimatorStats& s) { res.stats.merge(s); });
    res.seconds = timer.seconds();
    return res;
}

std::string study_csv(const StudyResult& r) {
    std::ostringstream s;
    s << "scenario,dim,k,estimator,n,trials,mean_rel_error,se_mean,rel_variance,rel_mse,se_mse,"
         "theory_rel_error,theory_rel_variance,theory_rel_mse,theory_rel_variance_limit,theory_source\n";
    for (const StudyRow& row : r.rows) {
        s << row.scenario << ',' << row.dim << ',' << row.k << ',' << study_row_label(row) << ','
          << row.n << ',' << row.trials << ',' << fmt(row.mean_error) << ',' << fmt(row.se_mean) << ','
          << fmt(row.rel_variance) << ',' << fmt(row.rel_mse) << ',' << fmt(row.se_mse) << ',';
        if (row.has_theory)
            s << fmt(row.th_error) << ',' << fmt(row.th_variance) << ',' << fmt(row.th_mse) << ','
              << fmt(row.th_variance_limit);
        else
            s << ",,,";
        s << ',' << row.theory_source << '\n';
    }
    return s.str();
}

std::string study_markdown(const StudyResult& r) {
    std::ostringstream s;
    s << "# Estimator study\n\n"
      << "Relative error e - 1 of the kNN density estimate (truth = 1), mean +- standard error over "
      << "the trials, with theory (exact finite-n order statistics, or quadrature over Beta(k, n-k+1)). "
      << "classic: sum of k / V(r_k); corrected: sum of k-1 / V(r_k); mse_optimal: (k-2)/(k-1) * corrected.\n\n";
    s << "seed " << r.options.seed << ", " << r.options.trials << " trials, n = " << r.options.n << ", "
      << fmt_fixed(r.seconds, 1) << " s on " << r.threads << " threads\n\n";
    std::string cur;
    for (const StudyRow& row : r.rows) {
        const std::string key = row.scenario + " " + std::to_string(row.dim) + "D";
        if (key != cur) {
            cur = key;
            s << "\n## " << key << " (n = " << row.n << ", " << row.trials << " trials, theory: " << row.theory_source
              << ")\n\n"
              << "| k | estimator | rel. error +- SE | theory | rel. variance | theory | rel. MSE +- SE | theory |\n"
              << "|---:|---|---:|---:|---:|---:|---:|---:|\n";
        }
        s << "| " << row.k << " | " << study_row_label(row) << " | " << fmt(row.mean_error) << " +- "
          << fmt(row.se_mean) << " | " << (row.has_theory ? fmt(row.th_error) : "") << " | " << fmt(row.rel_variance)
          << " | " << (row.has_theory ? fmt(row.th_variance) : "") << " | " << fmt(row.rel_mse) << " +- "
          << fmt(row.se_mse) << " | " << (row.has_theory ? fmt(row.th_mse) : "") << " |\n";
    }
    bool kernels = false;
    for (const StudyRow& row : r.rows) kernels |= row.scenario == "kernels";
    if (kernels) {
        s << "\n## Kernels: theory (exact)\n\n" << kernel_headline_table(r.options.kernels);
        for (int dim : r.options.dims)
            s << "\n## Kernels " << dim << "D: kept (classic) and discarded (corrected) k-th photon\n\n"
              << kernel_summary_table(r, dim, r.options.ks);
    }
    if (!r.notes.empty()) {
        s << "\n## Notes\n\n";
        for (const auto& n : r.notes) s << "- " << n << "\n";
    }
    s << "\nEstimator cases: " << r.stats.to_string() << "\n";
    return s.str();
}

std::string study_summary_table(const StudyResult& r, const std::string& scenario, int dim,
                                const std::vector<size_t>& ks) {
    // One column per registered estimator, in registry order.
    const std::vector<Estimator>& all = Estimator::all();
    std::ostringstream s;
    std::string names;
    s << "| k";
    for (const Estimator& e : all) {
        s << " | " << e.name() << " (theory)";
        names += (names.empty() ? "" : " / ") + std::string(e.name());
    }
    s << " | MSE " << names << " (theory) |\n|---:|";
    for (size_t i = 0; i <= all.size(); ++i) s << "---|";
    s << "\n";
    for (size_t k : ks) {
        std::vector<const StudyRow*> rows(all.size(), nullptr);
        for (const StudyRow& row : r.rows)
            if (row.scenario == scenario && row.dim == dim && row.k == k)
                for (size_t i = 0; i < all.size(); ++i)
                    if (row.estimator == all[i]) rows[i] = &row;
        if (!rows[0]) continue;
        s << "| " << k;
        for (const StudyRow* row : rows) {
            if (!row) { s << " | n/a"; continue; }
            s << " | " << fmt_fixed(row->mean_error, 4) << " +- " << fmt_fixed(row->se_mean, 4) << " ("
              << fmt_fixed(row->th_error, 4) << ")";
        }
        s << " | ";
        for (size_t i = 0; i < rows.size(); ++i)
            if (rows[i]) s << (i ? " / " : "") << fmt_fixed(rows[i]->rel_mse, 4);
        s << " (";
        for (size_t i = 0; i < rows.size(); ++i)
            if (rows[i]) s << (i ? " / " : "") << fmt_fixed(rows[i]->th_mse, 4);
        s << ") |\n";
    }
    return s.str();
}

// Theory values that are zero up to rounding print as 0.0000, not -0.0000.
std::string fmt_theory(double v) { return fmt_fixed(std::abs(v) < 1e-12 ? 0.0 : v, 4); }

std::string kernel_summary_table(const StudyResult& r, int dim, const std::vector<size_t>& ks) {
    std::ostringstream s;
    s << "| kernel | k | kept (classic): theory | measured +- SE | rel. MSE (theory) | discarded (corrected): theory "
         "| measured +- SE | rel. MSE (theory) |\n|---|---:|---:|---:|---:|---:|---:|---:|\n";
    const Estimator classic = Estimator::named("classic"), corrected = Estimator::named("corrected");
    for (const Kernel& kernel : r.options.kernels)
        for (size_t k : ks) {
            const StudyRow *kept = nullptr, *dropped = nullptr;
            for (const StudyRow& row : r.rows)
                if (row.scenario == "kernels" && row.dim == dim && row.k == k) {
                    if (row.estimator == classic.with_kernel(kernel)) kept = &row;
                    if (row.estimator == corrected.with_kernel(kernel)) dropped = &row;
                }
            if (!kept || !dropped) continue;
            s << "| " << kernel.label() << " | " << k;
            for (const StudyRow* row : {kept, dropped})
                s << " | " << fmt_theory(row->th_error) << " | " << fmt_fixed(row->mean_error, 4) << " +- "
                  << fmt_fixed(row->se_mean, 4) << " | " << fmt_fixed(row->rel_mse, 4) << " ("
                  << fmt_fixed(row->th_mse, 4) << ")";
            s << " |\n";
        }
    return s.str();
}

std::string kernel_headline_table(const std::vector<Kernel>& kernels) {
    std::ostringstream s;
    s << "| kernel | dim | n_d (registry) | M_d (mean of K) | limit bias m1 - 1 | kept k-th: bias - limit bias | "
         "bias kept k=10 | variance factor q |\n|---|---:|---:|---:|---:|---:|---:|---:|\n";
    for (const Kernel& kernel : kernels)
        for (int dim : {2, 3}) {
            const KernelMoments& m = kernel.moments(dim);
            char kept[64];
            std::snprintf(kept, sizeof kept, "%.4f / (k-1)", m.k1);
            const double b10 = Estimator::named("classic").with_kernel(kernel).uniform_theory(10, 0, 1.0, dim).error;
            s << "| " << kernel.label() << " | " << dim << " | " << fmt_fixed(kernel.normalisation(dim), 5) << " | "
              << fmt_fixed(kernel.profile_mean(dim), 5) << " | " << fmt_theory(m.m1 - 1.0) << " | " << kept << " | "
              << fmt_theory(b10) << " | " << fmt_fixed(m.variance_factor(), 4) << " |\n";
        }
    return s.str();
}

std::string study_sidecar_json(const StudyResult& r) {
    nlohmann::json j;
    const StudyOptions& o = r.options;
    std::vector<std::string> sc;
    for (auto s : o.scenarios) sc.push_back(scenario_name(s));
    j["command"] = "study";
    j["parameters"] = {{"dims", o.dims},       {"k", o.ks},
                       {"trials", o.trials},   {"n", o.n},
                       {"seed", o.seed},       {"scenarios", sc},
                       {"gradient_slope", o.gradient_slope},
                       {"boundary_distance", o.boundary_distance},
                       {"photon_map_size", o.photon_map_size},
                       {"photon_map_queries", o.photon_map_queries},
                       {"weights", "Exp(1), c_w = 2 (weighted scenario)"}};
    std::vector<std::string> kernels;
    for (const Kernel& k : o.kernels) kernels.push_back(k.label());
    j["parameters"]["kernels"] = kernels;
    j["time_seconds"] = r.seconds;
    j["threads"] = r.threads;
    j["git_revision"] = git_revision();
    std::time_t now = std::time(nullptr);
    char buf[64];
    std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
    j["finished_utc"] = buf;
    j["notes"] = r.notes;
    for (const auto& [name, count] : r.stats.fields()) j["estimator_cases"][name] = count;
    return j.dump(2) + "\n";
}

}  // namespace vpm
