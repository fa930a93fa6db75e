// vpm study [--out DIR] [--dims 2,3] [--k LIST] [--trials T] [--seed S] [--n N] [--scenarios LIST]
//           [--threads N] [--no-plots] [--quiet]
// Writes study.csv, study.md, study.json (sidecar) and, when /usr/bin/python3 with matplotlib is
// available, study_error.png / study_mse.png via tools/plot_study.py.
#include "cmd_study.h"

#include <CLI/CLI.hpp>
#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>
#include <sstream>
#include <vector>

#include "analysis/study/study.h"
#include "arguments.h"
#include "core/thread_limit.h"
#include "command.h"
#include "data_files.h"
#include "render/run/image_io.h"
#include "render/run/staged_file.h"
#include "core/error.h"

namespace vpm {

namespace {

template <class T>
std::vector<T> parse_list(const std::string& text, const char* what) {
    std::vector<T> out;
    std::stringstream ss(text);
    std::string item;
    while (std::getline(ss, item, ',')) {
        if (item.empty()) throw cli::UsageError(std::string(what) + ": '" + text + "' has an empty item (a comma too many)");
        try {
            size_t pos = 0;
            const long long v = std::stoll(item, &pos);
            if (pos != item.size() || v < 0) throw std::invalid_argument(item);
            out.push_back(static_cast<T>(v));
        } catch (const std::exception&) {
            throw cli::UsageError(std::string(what) + ": '" + item + "' is not a non-negative integer");
        }
    }
    if (out.empty()) throw cli::UsageError(std::string(what) + ": empty list");
    return out;
}

std::string shell_quote(const std::string& s) {
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

}  // namespace

int run_study(int argc, char** argv) {
    CLI::App app{"Estimator study: bias, variance and MSE of the classic (k), corrected (k-1) and\n"
                 "MSE-optimal (k-2) kNN density estimators against exact order-statistics theory\n"
                 "(Garcia, Urena & Sbert, EGSR 2013), plus non-uniform, boundary, weighted and\n"
                 "real-photon-map scenarios.",
                 "vpm study"};
    StudyOptions opt;
    std::string out_dir = "out/study", dims = "2,3", ks, scenarios;
    bool quiet = false, no_plots = false;
    int threads = 0;
    app.add_option("--out", out_dir, "output folder (created)")->capture_default_str();
    app.add_option("--dims", dims, "dimensions, comma-separated (2: disc / pi r^2, 3: ball / 4/3 pi r^3)")
        ->capture_default_str();
    app.add_option("--k", ks, "k values, comma-separated (default 2..256 log-spaced)");
    // Unsigned options refuse a sign: CLI11 would otherwise wrap "-5" to 2^64 - 5.
    app.add_option("--trials", opt.trials, "trials per scenario and dimension (photon_map: a quarter, photon_pass: a tenth of them, at least 2)")
        ->check(CLI::NonNegativeNumber)->capture_default_str();
    app.add_option("--n", opt.n, "points per trial (must exceed the largest k)")->check(CLI::NonNegativeNumber)->capture_default_str();
    app.add_option("--seed", opt.seed, "random seed (results are identical on any thread count)")
        ->check(CLI::NonNegativeNumber)->capture_default_str();
    app.add_option("--scenarios", scenarios,
                   "comma-separated: uniform, gradient, gaussian, boundary, weighted, photon_map, photon_pass, "
                   "kernels, beam, stratified (point sets: independent, stratified, jittered, sobol, lattice; "
                   "docs/stratified_sampling.md), photon_beams (docs/photon_beams.md), walks (random walks, "
                   "docs/walk_correlation.md) (default: all but beam, whose trials cost O(n^2), stratified, "
                   "photon_beams and walks)");
    app.add_option("--photon-map-size", opt.photon_map_size, "photons per map (photon_map) / photons emitted per map (photon_pass)")
        ->check(CLI::NonNegativeNumber)->capture_default_str();
    app.add_option("--walk-density", opt.walk_density, "walks scenario: photons per mean free path cubed (the truth)")
        ->check(CLI::PositiveNumber)->capture_default_str();
    app.add_option("--walks-per-trial", opt.walks_per_trial, "walks scenario: random walks per trial (at least 16 x the largest k)")
        ->check(CLI::NonNegativeNumber)->capture_default_str();
    app.add_option("--threads", threads, "worker threads (0: all cores)")->check(CLI::Range(0, vpm::kMaxThreads))->capture_default_str();
    app.add_flag("--no-plots", no_plots, "do not run tools/plot_study.py");
    app.add_flag("-q,--quiet", quiet, "no progress lines");
    if (!vpm::cli::parse_arguments(app, argc, argv)) return 0;
    {
        opt.dims = parse_list<int>(dims, "--dims");
        if (!ks.empty()) opt.ks = parse_list<size_t>(ks, "--k");
        if (!scenarios.empty()) {
            opt.scenarios.clear();
            std::stringstream ss(scenarios);
            std::string item;
            while (std::getline(ss, item, ',')) {
                if (item.empty()) throw cli::UsageError("--scenarios: '" + scenarios + "' has an empty item (a comma too many)");
                StudyScenario sc;
                try {
                    sc = parse_scenario(item);
                } catch (const Error& e) {
                    throw cli::UsageError(std::string("--scenarios: ") + e.what());
                }
                if (std::find(opt.scenarios.begin(), opt.scenarios.end(), sc) != opt.scenarios.end())
                    throw cli::UsageError("--scenarios: '" + item + "' is listed twice");
                opt.scenarios.push_back(sc);
            }
        }
        for (size_t i = 0; i < opt.dims.size(); ++i)
            for (size_t j = 0; j < i; ++j)
                if (opt.dims[i] == opt.dims[j]) throw cli::UsageError("--dims: " + std::to_string(opt.dims[i]) + " is listed twice");
        std::unique_ptr<tbb::global_control> gc;
        if (threads > 0)
            gc = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, threads);
        // Every option is checked (memory included) before the output folder is touched; a bad value
        // is a bad command line (exit 2), like one CLI11 refuses.
        try {
            validate_study_options(opt);
        } catch (const cli::UsageError&) {
            throw;
        } catch (const Error& e) {
            throw cli::UsageError(e.what());
        }
        auto log = [quiet](const std::string& s) {
            if (!quiet) std::cerr << s << std::endl;
        };
        // Before the work: an unwritable --out fails now, not after minutes of trials.
        const std::filesystem::path out(out_dir);
        prepare_output_folder(out);
        for (const char* name : {"study.csv", "study.md", "study.json"}) check_output_file(out / name);
        const StudyResult res = run_estimator_study(opt, log);
        write_text_atomic(out / "study.csv", study_csv(res));
        write_text_atomic(out / "study.md", study_markdown(res));
        write_text_atomic(out / "study.json", study_sidecar_json(res));
        for (const auto& n : res.notes) log("note: " + n);
        for (int dim : res.options.dims) {
            bool has = false;
            for (const auto& r : res.rows) has |= r.scenario == "uniform" && r.dim == dim;
            if (!has || quiet) continue;
            std::cout << "uniform " << dim << "D, relative error (theory):\n"
                      << study_summary_table(res, "uniform", dim, {3, 5, 10, 50, 100}) << "\n";
        }
        bool kernels = false;
        for (const auto& r : res.rows) kernels |= r.scenario == "kernels";
        if (kernels && !quiet) {
            std::cout << "kernels: theory (exact, no Monte Carlo)\n" << kernel_headline_table(res.options.kernels) << "\n";
            for (int dim : res.options.dims)
                std::cout << "kernels " << dim << "D, relative error: theory, measured +- SE, relative MSE (theory):\n"
                          << kernel_summary_table(res, dim, {3, 5, 10, 50}) << "\n";
        }
        log("study: wrote " + (out / "study.csv").string() + ", study.md, study.json in " +
            std::to_string(res.seconds) + " s");
        if (!no_plots) {
            const std::filesystem::path script = cli::data_file("tools/plot_study.py");
            if (std::filesystem::exists("/usr/bin/python3") && std::filesystem::exists(script)) {
                const std::string cmd = "/usr/bin/python3 " + shell_quote(script.string()) + " " +
                                        shell_quote((out / "study.csv").string()) + " " + shell_quote(out.string());
                const auto before = std::filesystem::file_time_type::clock::now();
                const int rc = std::system(cmd.c_str());
                if (rc != 0) log("study: plotting failed (exit " + std::to_string(rc) + "); the tables are written");
                // The plots this run wrote (the script replaces each study_*.png atomically).
                std::vector<std::string> plots;
                for (const auto& e : std::filesystem::directory_iterator(out)) {
                    const std::string name = e.path().filename().string();
                    std::error_code ec;
                    if (name.rfind("study_", 0) == 0 && e.path().extension() == ".png" &&
                        std::filesystem::last_write_time(e.path(), ec) >= before - std::chrono::seconds(1) && !ec)
                        plots.push_back(e.path().string());
                }
                std::sort(plots.begin(), plots.end());
                for (const auto& p : plots) log("study: plot " + p);
            } else {
                log("study: plots skipped (/usr/bin/python3 or " + script.string() + " missing)");
            }
        }
        return 0;
    }
}

}  // namespace vpm

VPM_REGISTER_COMMAND({"study", "the estimator study: bias, variance and MSE of classic, corrected and (k-2) scales", vpm::run_study});
