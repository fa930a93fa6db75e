// vpm bench equal-time CONFIG... [--reference-spp N] [--size WxH] [--photons N] [--pm-spp N] [--threads N]
//
// Error at equal time: for each scene config, renders
//   1. a long path-traced reference (integrator "path", --reference-spp samples per pixel),
//      cached under out/equal_time/ (reused when the file exists; --fresh re-renders it);
//   2. the photon map (corrected estimator, k = 32, NEE for single scattering, --photons photons),
//      timing the whole run: photon pass + kd-tree + render;
//   3. the path tracer with as many samples per pixel as fit in that same wall time (seconds per
//      sample measured by a short calibration render, then a render at the matched spp, redone
//      once with a corrected spp when its time is off by more than 15%);
// and prints the error of (2) and (3) against (1) by a named metric (--metric, relMSE by default:
// lib/analysis/metrics/error_metrics.h), the reference's noise floor subtracted (the reference renders in
// independent passes and keeps its variance image beside it), and their ratio.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <thread>

#include <unistd.h>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <tbb/global_control.h>
#include <tbb/info.h>

#include "analysis/metrics/error_metrics.h"
#include "analysis/metrics/reference_noise.h"
#include "analysis/matrix/scene_matrix.h"
#include "analysis/metrics/reference_samples.h"
#include "arguments.h"
#include "core/thread_limit.h"
#include "data_files.h"
#include "command.h"
#include "core/error.h"
#include "core/progress.h"
#include "render/run/image_io.h"
#include "render/run/staged_file.h"
#include "render/run/run.h"

namespace {

namespace fs = std::filesystem;

struct Timed {
    vpm::Image image;
    vpm::Image variance;   // with pass variance and two or more passes
    double seconds = 0.0;   // wall time of the run (all phases)
    int spp = 0;
};

// The reference runs on its own random streams: with the same seed and stream it would repeat the
// first samples of the equal-time path-traced image, and their errors would be correlated.
constexpr uint64_t kReferenceStream = 7919;

Timed run(const std::string& config, std::vector<std::string> sets, uint64_t stream_offset = 0, bool pass_variance = false) {
    const vpm::RunConfig run_config = vpm::RunConfig::load(config, sets);
    vpm::RunOptions o;
    o.progress = false;
    o.stream_offset = stream_offset;
    o.pass_variance = pass_variance;
    const vpm::Timer t;
    vpm::RunResult r = vpm::run(run_config, o);
    Timed out;
    out.seconds = t.seconds();
    out.image = std::move(r.image);
    out.variance = std::move(r.variance);
    out.spp = run_config.render.spp;
    return out;
}

int run_equal_time(int argc, char** argv) {
    CLI::App app("Error at equal time: photon map (corrected, k = 32) vs path tracer, both against a long "
                 "path-traced reference (cached under out/equal_time/).",
                 "vpm bench equal-time");
    std::vector<std::string> configs;
    int reference_spp = 1024, threads = 0, pm_spp = 16;
    int64_t photons = 1000000;
    std::string size = "128x128", out_dir = "out/equal_time";
    bool fresh = false;
    std::string metric_text = "relmse";
    double epsilon = vpm::kDefaultMetricEpsilon;
    app.add_option("configs", configs, "Scene configs (TOML)")->required();
    app.add_option("--metric", metric_text, "The error: relmse, relrmse or smape (docs/metrics.md)")->capture_default_str();
    app.add_option("--epsilon", epsilon, "eps of relmse and smape")
        ->capture_default_str()
        ->check(vpm::cli::finite_in(1e-12, 1e12, "a number > 0"));
    app.add_option("--reference-spp", reference_spp, "Samples per pixel of the path-traced reference")
        ->capture_default_str()->check(CLI::Range(1, 1 << 20));
    app.add_option("--pm-spp", pm_spp, "Samples per pixel of the photon-map render")->capture_default_str()->check(CLI::Range(1, 1 << 20));
    app.add_option("--photons", photons, "Photons emitted for the photon map")->capture_default_str()->check(CLI::Range(int64_t(1000), int64_t(1) << 32));
    app.add_option("--size", size, "Image size WxH (overrides render.width/height)")->capture_default_str();
    app.add_option("--threads", threads, "Worker threads (0: all cores)")->capture_default_str()->check(CLI::Range(0, vpm::kMaxThreads));
    app.add_option("--out", out_dir, "Folder for the cached references and the results")->capture_default_str();
    app.add_flag("--fresh", fresh, "Re-render the references even when cached");
    if (!vpm::cli::parse_arguments(app, argc, argv)) return 0;
    vpm::MetricOptions metric;
    try {
        metric.metric = vpm::parse_error_metric(metric_text);
    } catch (const vpm::Error& e) {
        throw vpm::cli::UsageError(std::string("--metric: ") + e.what());
    }
    metric.epsilon = epsilon;
    const std::string mname = vpm::metric_name(metric.metric);

    int w = 0, h = 0;
    char x = 0;
    std::istringstream ss(size);
    if (!(ss >> w >> x >> h) || x != 'x' || w < 1 || h < 1 || !ss.eof()) {
        throw vpm::cli::UsageError("--size: expected WxH with positive integers, e.g. 128x128, got '" + size + "'");
    }
    vpm::prepare_output_folder(out_dir);   // before the work
    const int n_threads = threads > 0 ? threads : tbb::info::default_concurrency();
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(n_threads));
    const std::vector<std::string> common = {"render.width=" + std::to_string(w), "render.height=" + std::to_string(h)};

    nlohmann::json results = nlohmann::json::array();
    std::printf("%s, the reference's noise floor subtracted where known\n\n", vpm::metric_formula(metric.metric, metric.epsilon).c_str());
    std::printf("| scene | reference (noise floor) | photon map: time, %s | path tracer: spp, time, %s | %s ratio PT/PM |\n",
                mname.c_str(), mname.c_str(), mname.c_str());
    std::printf("|---|---|---|---|---|\n");
    for (const auto& config : configs) {
        const std::string stem = fs::path(config).stem().string();
        const fs::path ref_path =
            fs::path(out_dir) / (stem + "_reference_" + std::to_string(w) + "x" + std::to_string(h) + "_" +
                                 std::to_string(reference_spp) + "spp.exr");
        double ref_seconds = 0.0;
        if (fresh || !fs::exists(ref_path)) {
            std::cerr << stem << ": rendering the reference (" << reference_spp << " spp) ...\n";
            auto sets = common;
            sets.push_back("render.integrator=\"path\"");
            sets.push_back("render.spp=" + std::to_string(reference_spp));
            // In independent passes, for its variance image (the noise floor).
            for (int passes : {16, 8, 4, 2})
                if (reference_spp % passes == 0) {
                    sets.push_back("render.passes=" + std::to_string(passes));
                    break;
                }
            Timed r = run(config, sets, kReferenceStream, true);
            ref_seconds = r.seconds;
            fs::create_directories(ref_path.parent_path());
            const fs::path variance_path = vpm::variance_path_for(ref_path);
            if (r.variance.width > 0) vpm::write_exr(variance_path, r.variance);
            else fs::remove(variance_path);
            vpm::write_exr(ref_path, r.image);
            std::cerr << stem << ": reference in " << ref_seconds << " s -> " << ref_path << "\n";
        } else {
            std::cerr << stem << ": reference from " << ref_path << "\n";
        }
        const vpm::NoisyReference noisy = vpm::load_reference(ref_path);
        const vpm::Image& ref = noisy.image;
        auto error_of = [&](const vpm::Image& im) {
            return vpm::measure_error(im, ref, metric, noisy.variance ? &*noisy.variance : nullptr);
        };

        auto pm_sets = common;
        for (const char* s : {"render.integrator=\"photon_map\"", "photons.estimator=\"corrected\"", "photons.k=32",
                              "photons.direct=\"nee\""})
            pm_sets.push_back(s);
        pm_sets.push_back("photons.count=" + std::to_string(photons));
        pm_sets.push_back("render.spp=" + std::to_string(pm_spp));
        const Timed pm = run(config, pm_sets);
        const vpm::MetricValue pm_m = error_of(pm.image);
        const double pm_err = pm_m.value;
        std::cerr << stem << ": photon map (" << pm.spp << " spp) in " << pm.seconds << " s, " << vpm::describe(pm_m) << "\n";

        // Path tracer: seconds per spp from a calibration render, then the matched spp.
        auto pt_sets = common;
        pt_sets.push_back("render.integrator=\"path\"");
        const int calib_spp = 4;
        auto calib_sets = pt_sets;
        calib_sets.push_back("render.spp=" + std::to_string(calib_spp));
        const Timed calib = run(config, calib_sets);
        const double per_spp = calib.seconds / calib_spp;
        int spp = std::max(1, int(std::lround(pm.seconds / per_spp)));
        auto pt_run = [&](int n) {
            auto s = pt_sets;
            s.push_back("render.spp=" + std::to_string(n));
            return run(config, s);
        };
        Timed pt = pt_run(spp);
        if (std::abs(pt.seconds / pm.seconds - 1.0) > 0.15) {   // calibration off (fixed costs, load): once more
            spp = std::max(1, int(std::lround(spp * pm.seconds / pt.seconds)));
            pt = pt_run(spp);
        }
        const vpm::MetricValue pt_m = error_of(pt.image);
        const double pt_err = pt_m.value;
        std::cerr << stem << ": path tracer " << spp << " spp in " << pt.seconds << " s, " << vpm::describe(pt_m) << "\n";
        const uint64_t pixels = uint64_t(w) * uint64_t(h);
        for (const auto& [what, n] : {std::pair<std::string, int>{"the photon map", pm.spp}, {"the path tracer", spp}})
            if (const std::string warn = vpm::more_samples_warning(stem + ": " + what + " (" + std::to_string(n) + " spp)",
                                                                   uint64_t(n) * pixels, ref_path.string(),
                                                                   uint64_t(reference_spp) * pixels);
                !warn.empty())
                std::cerr << warn << "\n";

        const std::string floor_text = pm_m.floor_known() ? std::to_string(pm_m.floor) : std::string("unknown");
        std::printf("| %s | %d spp (%s) | %.2f s, %.4g | %d spp, %.2f s, %.4g | %.3g |\n", stem.c_str(), reference_spp,
                    floor_text.c_str(), pm.seconds, pm_err, spp, pt.seconds, pt_err, pt_err / pm_err);
        std::fflush(stdout);
        results.push_back({{"config", config},
                           {"size", {w, h}},
                           {"threads", n_threads},
                           {"metric", mname},
                           {"metric_formula", vpm::metric_formula(metric.metric, metric.epsilon)},
                           {"reference", {{"file", ref_path.string()}, {"spp", reference_spp}, {"noise_source", noisy.noise_source}}},
                           {"photon_map", {{"photons", photons}, {"spp", pm.spp}, {"seconds", pm.seconds}, {"error", pm_err},
                                           {"error_raw", pm_m.raw}}},
                           {"path", {{"spp", spp}, {"seconds", pt.seconds}, {"error", pt_err}, {"error_raw", pt_m.raw}}},
                           {"error_ratio_path_over_photon_map", pt_err / pm_err}});
    }
    const fs::path json_path = fs::path(out_dir) / "equal_time.json";
    fs::create_directories(json_path.parent_path());
    vpm::write_text_atomic(json_path, results.dump(2) + "\n");
    std::cerr << "wrote " << json_path << "\n";
    return 0;
}


// vpm bench matrix: the scene matrix of issue 20 (lib/analysis/matrix/scene_matrix.h).
int run_matrix(int argc, char** argv) {
    CLI::App app("The scene matrix: homogeneous box and sphere, the Gaussian blob and the plume across optical\n"
                 "thickness, albedo, g, lights and scale; per cell the path tracer, the photon map's defaults and\n"
                 "each gather forced, at equal time, against cached path-traced references. Writes OUT/MATRIX.md,\n"
                 "OUT/matrix.csv and OUT/matrix.png/.pdf/.svg (tools/plot_matrix.py, when matplotlib is there).",
                 "vpm bench matrix");
    std::string out = "out/matrix", only, media = vpm::cli::data_file("media").string();
    vpm::MatrixOptions o;
    bool quick = false, no_plot = false;
    int threads = 0;
    double budget = -1, reference = -1, max_tau = 0;
    app.add_option("--out", out, "Folder for scenes/, references/ (the cache), MATRIX.md, matrix.csv")->capture_default_str();
    app.add_flag("--quick", quick, "4 cells (one scaled), 32x32, 1 s per method, 4 s references: about a minute");
    app.add_option("--budget", budget, "Seconds per method and cell (default 4; --quick 1)")->check(vpm::cli::finite_in(0.01, 3600.0, "a number in [0.01, 3600]"));
    app.add_option("--reference-seconds", reference, "Path tracer seconds per reference (default 30; --quick 4)")
        ->check(vpm::cli::finite_in(0.01, 1e6, "a number in [0.01, 1e6]"));
    app.add_option("--size", o.size, "Image width = height (default 64; --quick 32)")->check(CLI::Range(4, 4096));
    app.add_option("--threads", threads, "Worker threads (0: all cores)")->capture_default_str()->check(CLI::Range(0, vpm::kMaxThreads));
    app.add_option("--only", only, "Run only cells whose id (e.g. box-tau10-a0.9-g0-point-s1) or group contains TEXT");
    app.add_option("--max-tau", max_tau, "Run only cells of optical thickness <= T (with --only: both must hold; 0: no limit)")
        ->check(vpm::cli::finite_in(0.0, HUGE_VAL, "a finite number >= 0"));
    app.add_option("--media", media, "Folder with blob.vdb and plume.vdb")->capture_default_str()->check(CLI::ExistingDirectory);
    app.add_flag("--no-plot", no_plot, "Do not run tools/plot_matrix.py");
    app.add_option("--set", o.method_sets,
                   "KEY=VALUE for every compared run, not the references (repeatable; photons.* or render.seed), "
                   "e.g. --set photons.store_probability='\"auto\"' to measure a default before changing it");
    if (!vpm::cli::parse_arguments(app, argc, argv)) return 0;
    for (const std::string& s : o.method_sets) vpm::check_matrix_method_set(s);
    o.quick = quick;
    o.budget = budget > 0 ? budget : (quick ? 1.0 : 4.0);
    o.reference_seconds = reference > 0 ? reference : (quick ? 4.0 : 30.0);
    if (quick && app.count("--size") == 0) o.size = 32;
    o.media = media;
    o.out = out;
    o.log = &std::cerr;
    if (!only.empty() || max_tau > 0)
        o.filter = [only, max_tau](const vpm::MatrixCell& c) {
            const bool named = only.empty() || c.id().find(only) != std::string::npos || c.group.find(only) != std::string::npos;
            return named && (max_tau <= 0 || c.tau <= max_tau);
        };
    if (o.filter) {   // a selection that matches nothing is a bad command line, before any output
        bool any = false;
        for (const vpm::MatrixCell& c : vpm::matrix_cells(o.quick)) any = any || o.filter(c);
        if (!any)
            throw vpm::cli::UsageError("--only '" + only + "'" + (max_tau > 0 ? " with --max-tau" : std::string()) +
                                       ": no cell of the matrix matches (see vpm bench matrix --help)");
    }
    vpm::prepare_output_folder(out);   // before the work
    const fs::path md = fs::path(out) / "MATRIX.md", csv = fs::path(out) / "matrix.csv";
    vpm::check_output_file(md);
    vpm::check_output_file(csv);
    const int n_threads = threads > 0 ? threads : tbb::info::default_concurrency();
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(n_threads));

    char host[256] = "unknown";
    gethostname(host, sizeof host - 1);
    std::ostringstream machine;
    machine << host << ", " << n_threads << " of " << std::thread::hardware_concurrency() << " threads";
    std::string command = "vpm bench matrix";
    for (int i = 1; i < argc; ++i) command += std::string(" ") + argv[i];
    auto write = [&](const vpm::MatrixReport& r) {   // after every cell: a stopped run keeps what it finished
        vpm::write_text_atomic(md, r.to_markdown(command, machine.str()));
        vpm::write_text_atomic(csv, r.to_csv());
    };
    const vpm::MatrixReport report = vpm::run_scene_matrix(o, write);
    write(report);
    std::cerr << "wrote " << md.string() << " and " << csv.string() << " (" << report.rows.size() << " cells, "
              << report.seconds << " s; references rendered " << report.references_rendered << ", reused "
              << report.references_reused << ")\n";
    const fs::path script = vpm::cli::data_file("tools/plot_matrix.py");
    if (!no_plot) {
        if (!fs::exists("/usr/bin/python3") || !fs::exists(script)) {
            std::cerr << "matrix: plot skipped (/usr/bin/python3 or " << script.string() << " missing)\n";
        } else if (std::system(("/usr/bin/python3 '" + script.string() + "' '" + csv.string() + "'").c_str()) != 0) {
            std::cerr << "matrix: plotting failed (is python3-matplotlib installed?); the tables are written\n";
        }
    }
    return 0;
}

int run_bench(int argc, char** argv) {
    if (argc < 2) throw vpm::cli::UsageError("no mode given (allowed: equal-time, matrix; see vpm bench --help)");
    if (std::string(argv[1]) == "--help" || std::string(argv[1]) == "-h") {
        std::printf("usage: vpm bench MODE [options]\n\nmodes:\n  equal-time   photon map vs path tracer error at "
                    "equal wall time (vpm bench equal-time --help)\n  matrix       the scene matrix: photon map vs path tracer across media, lights and scales (vpm bench matrix --help)\n\nSpeed benchmarks are the bench_* programs "
                    "(BENCHMARKS.md).\n");
        return 0;
    }
    const std::string mode = argv[1];
    std::string name = "vpm bench " + mode;
    std::vector<char*> args;
    args.push_back(name.data());
    for (int i = 2; i < argc; ++i) args.push_back(argv[i]);
    if (mode == "equal-time") return run_equal_time(int(args.size()), args.data());
    if (mode == "matrix") return run_matrix(int(args.size()), args.data());
    throw vpm::cli::UsageError("unknown mode '" + mode + "' (allowed: equal-time, matrix)");
}

}  // namespace

VPM_REGISTER_COMMAND({"bench", "benchmark modes: equal-time error of photon map vs path tracer, the scene matrix", run_bench});
