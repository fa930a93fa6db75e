// vpm sweep SWEEP.toml [--out DIR] [--shard i/N] [--jobs J] [--max-runs N] [--threads T] [--dry-run]
//                      [--no-plots] [--quiet]
// vpm sweep merge DIR... [--out DIR] [--no-plots] [--quiet]
// Parameter sweeps with error against run time (issue 5). The work is in lib/analysis/sweep*.
#include <CLI/CLI.hpp>
#include <tbb/global_control.h>

#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "analysis/sweep/sweep.h"
#include "analysis/sweep/sweep_plan.h"
#include "arguments.h"
#include "core/thread_limit.h"
#include "command.h"
#include "data_files.h"
#include "core/error.h"

namespace vpm {

namespace {

void parse_shard(const std::string& text, int& shard, int& shards) {
    const auto slash = text.find('/');
    try {
        if (slash == std::string::npos) throw std::invalid_argument(text);
        size_t p1 = 0, p2 = 0;
        shard = std::stoi(text.substr(0, slash), &p1);
        shards = std::stoi(text.substr(slash + 1), &p2);
        if (p1 != slash || p2 != text.size() - slash - 1) throw std::invalid_argument(text);
    } catch (const std::exception&) {
        throw Error("--shard " + text + ": expected i/N, e.g. 0/4 (i from 0 to N-1)");
    }
    if (shards < 1 || shard < 0 || shard >= shards)
        throw Error("--shard " + text + ": expected 0 <= i < N, e.g. 0/4 ... 3/4");
}

int run_merge(int argc, char** argv) {
    CLI::App app{"Merge the runs*.csv of sweep folders (shards) into one table and write its report\n"
                 "(points.csv, summary.md, plots). Rows are identified by their hash: duplicates are dropped.",
                 "vpm sweep merge"};
    std::vector<std::string> dirs;
    std::string out;
    bool quiet = false, no_plots = false;
    app.add_option("DIRS", dirs, "sweep output folders (--out of each shard)")->required()->check(CLI::ExistingDirectory);
    app.add_option("--out", out, "merged folder (default: the first DIR)");
    app.add_flag("--no-plots", no_plots, "do not run tools/plot_sweep.py");
    app.add_flag("-q,--quiet", quiet, "no progress lines");
    if (!vpm::cli::parse_arguments(app, argc, argv)) return 0;
    auto log = [quiet](const std::string& s) {
        if (!quiet) std::cerr << s << std::endl;
    };
    std::vector<std::filesystem::path> paths(dirs.begin(), dirs.end());
    const std::filesystem::path target = out.empty() ? paths[0] : std::filesystem::path(out);
    merge_sweeps(paths, target, log);
    if (!no_plots) plot_sweep(target, vpm::cli::data_file("tools/plot_sweep.py"), log);
    std::cerr << "vpm sweep merge: wrote " << (target / "runs.csv").string() << ", points.csv, summary.md" << std::endl;
    return 0;
}

int run_sweep_command(int argc, char** argv) {
    if (argc >= 2 && std::string(argv[1]) == "merge") {
        std::string program = "vpm sweep merge";
        std::vector<char*> args(argv + 1, argv + argc);
        args[0] = program.data();
        return run_merge(int(args.size()), args.data());
    }
    CLI::App app{"Parameter sweep: runs the photon-map renderer over the Cartesian product of the sweep file's\n"
                 "axes (k, estimator, photons.count, any scene key), R repeats each, plus the path tracer at\n"
                 "increasing spp, and reports each run's error against a reference and its run time.\n"
                 "Resumable (finished rows are skipped), shardable (--shard i/N, then `vpm sweep merge`).\n"
                 "See docs/experiments.md, \"Parameter sweeps\", for the file format and the metrics.\n\n"
                 "  vpm sweep merge DIR... [--out DIR]   merge shard folders",
                 "vpm sweep"};
    std::string file, out, shard = "0/1";
    SweepOptions opt;
    int threads = 0;
    bool quiet = false, no_plots = false, dry_run = false;
    app.add_option("SWEEP", file, "sweep file (TOML), e.g. configs/sweeps/quick.toml")->required();
    app.add_option("--out", out, "output folder (default: out/sweeps/<sweep file name>)");
    app.add_option("--shard", shard, "run only slice i of N (0 <= i < N), for job arrays; merge afterwards")
        ->capture_default_str();
    app.add_option("--jobs", opt.jobs, "runs at once (each run also uses --threads)")->capture_default_str()->check(CLI::Range(1, 256));
    app.add_option("--threads", threads, "worker threads per process (0: all cores)")->capture_default_str()->check(CLI::Range(0, vpm::kMaxThreads));
    // Unsigned: a sign is refused (CLI11 would wrap -1 to 2^64 - 1).
    app.add_option("--max-runs", opt.max_runs, "stop after this many new runs (0: all); rerun to continue")
        ->check(CLI::NonNegativeNumber)->capture_default_str();
    app.add_flag("--references-only", opt.references_only,
                 "render the references of the whole sweep and stop (before a job array shares --out)");
    app.add_flag("--dry-run", dry_run, "validate the sweep and print the plan, run nothing");
    app.add_flag("--no-plots", no_plots, "do not run tools/plot_sweep.py");
    app.add_flag("-q,--quiet", quiet, "no progress lines");
    if (!vpm::cli::parse_arguments(app, argc, argv)) return 0;
    parse_shard(shard, opt.shard, opt.shards);
    auto log = [quiet](const std::string& s) {
        if (!quiet) std::cerr << s << std::endl;
    };
    opt.log = log;
    opt.progress = !quiet;
    opt.out = out.empty() ? std::filesystem::path("out/sweeps") / std::filesystem::path(file).stem() : std::filesystem::path(out);
    for (int i = 0; i < argc; ++i) opt.command_line.push_back(argv[i]);
    std::unique_ptr<tbb::global_control> gc;
    if (threads > 0) gc = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, size_t(threads));

    const SweepPlan plan = plan_sweep(load_sweep(file), log);
    if (dry_run) {
        size_t mine = 0;
        for (const auto& r : plan.runs) mine += int(r.index % size_t(opt.shards)) == opt.shard;
        std::cout << file << ": " << plan.runs.size() << " runs (" << mine << " in shard " << shard << "), "
                  << plan.references.size() << " reference scene(s), " << plan.spec.repeats << " repeats\n";
        for (const auto& r : plan.runs) {
            if (int(r.index % size_t(opt.shards)) != opt.shard) continue;
            std::cout << r.index << " " << r.hash << " " << r.method << " r" << r.repeat;
            for (size_t a = 0; a < plan.spec.axes.size(); ++a)
                if (!r.values[a].empty()) std::cout << " " << plan.spec.axes[a].name << "=" << r.values[a];
            if (r.method == "path") std::cout << " spp=" << r.spp;
            std::cout << "\n";
        }
        return 0;
    }
    const SweepOutcome res = run_sweep(plan, opt);
    if (!no_plots) plot_sweep(opt.out, vpm::cli::data_file("tools/plot_sweep.py"), log);
    std::cerr << "vpm sweep: " << res.ran << " runs in " << res.seconds << " s (" << res.skipped << " already done"
              << (res.remaining ? ", " + std::to_string(res.remaining) + " left for the next call" : std::string()) << "); wrote "
              << res.csv.string() << ", points.csv, summary.md, sweep.json in " << opt.out.string() << std::endl;
    if (opt.shards > 1)
        std::cerr << "vpm sweep: shard " << shard << " done; once every shard has finished: vpm sweep merge "
                  << "<each shard's --out folder> --out MERGED (or the shared folder alone)" << std::endl;
    return 0;
}

}  // namespace

}  // namespace vpm

VPM_REGISTER_COMMAND({"sweep", "parameter sweeps: error against run time over k, estimator, photons, media (resumable, shardable)",
                      vpm::run_sweep_command});
