// vpm render CONFIG [-o OUT.exr] [--set KEY=VALUE]... [--threads N] [--quiet]
#include <filesystem>
#include <iostream>
#include <sstream>

#include <CLI/CLI.hpp>
#include <tbb/global_control.h>
#include <tbb/info.h>

#include "command.h"
#include "core/progress.h"
#include "analysis/error_metrics.h"
#include "core/error.h"
#include "render/image_io.h"
#include "render/run.h"

namespace {

int run_render(int argc, char** argv) {
    CLI::App app("Render a scene config to an OpenEXR image, a PNG preview and a JSON sidecar.", "vpm render");
    std::string config, output;
    std::vector<std::string> sets;
    int threads = -1;
    bool quiet = false;
    app.add_option("config", config, "Scene config (TOML)")->required();
    app.add_option("-o,--output", output, "Output EXR (default: render.output from the config)");
    app.add_option("--set", sets, "Override a config key by dotted path, e.g. media.0.sigma_t_scale=10 (repeatable)");
    app.add_option("--threads", threads, "Worker threads (0: all cores; default: render.threads)")->check(CLI::Range(0, 4096));
    app.add_flag("-q,--quiet", quiet, "No progress bar or log on stderr");
    std::string reference;
    app.add_option("--reference", reference,
                   "Reference EXR: after every pass, write the error of the mean so far against it to OUT.passes.csv "
                   "(pass, spp, elapsed seconds, relative RMSE, relative mean error)")
        ->check(CLI::ExistingFile);
    CLI11_PARSE(app, argc, argv);

    // Command-line settings go through the same validation as the file and end up in the
    // resolved config, so the sidecar says exactly what ran.
    if (!output.empty()) sets.push_back("render.output=\"" + output + "\"");
    if (threads >= 0) sets.push_back("render.threads=" + std::to_string(threads));

    const vpm::Timer load_timer;
    const vpm::RunConfig run_config = vpm::RunConfig::load(config, sets);
    const vpm::RenderSettings& render = run_config.render;
    const double load_seconds = load_timer.seconds();
    const int n_threads = render.threads > 0 ? render.threads : tbb::info::default_concurrency();
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(n_threads));

    std::ostream* log = quiet ? nullptr : &std::cerr;
    if (log) {
        *log << "load: " << config << " in " << load_seconds << " s, " << n_threads << " threads\n";
        for (const auto& line : run_config.scene->build_log) *log << "  " << line << "\n";
    }
    vpm::RunOptions options;
    options.progress = !quiet;
    options.log = log;
    std::ostringstream passes_csv;
    vpm::RunError last_error;
    if (!reference.empty()) {
        const vpm::Image ref = vpm::read_exr(reference);
        if (ref.width != render.width || ref.height != render.height)
            throw vpm::Error(reference + ": reference is " + std::to_string(ref.width) + "x" + std::to_string(ref.height) +
                             ", the render " + std::to_string(render.width) + "x" + std::to_string(render.height));
        passes_csv.precision(9);
        passes_csv << "pass,spp,elapsed_s,rel_rmse,rel_mean_error\n";
        int pass = 0, spp = 0;
        options.on_pass = [&passes_csv, &last_error, ref, pass, spp](const vpm::Image& mean, const vpm::PassStats& p) mutable {
            last_error = vpm::run_error(mean, ref);
            spp += p.spp;
            passes_csv << ++pass << ',' << spp << ',' << p.elapsed << ',' << last_error.rel_rmse << ','
                       << last_error.rel_mean_error << '\n';
        };
    }
    vpm::RunResult result = vpm::run(run_config, options);
    if (!reference.empty()) {
        result.record.set("reference.file", reference);
        result.record.set("reference.rel_rmse", last_error.rel_rmse);
        result.record.set("reference.rel_mean_error", last_error.rel_mean_error);
    }
    result.record.phase("load", load_seconds);
    result.record.set("threads", n_threads);
    std::vector<std::string> args(argv, argv + argc);
    result.record.set("command_line", args);
    vpm::write_run_outputs(render.output, result, render.exposure);
    if (!reference.empty()) {
        std::filesystem::path csv = render.output;
        csv.replace_extension(".passes.csv");
        vpm::write_text_atomic(csv, passes_csv.str());
        if (log) *log << "error against " << reference << ": rel RMSE " << last_error.rel_rmse << " after "
                      << result.stats.passes.size() << " pass(es); per pass in " << csv.string() << "\n";
    }
    if (log) *log << "wrote " << render.output << " (+ .png, .json)\n";
    return 0;
}

}  // namespace

VPM_REGISTER_COMMAND({"render", "render a scene config to EXR + PNG preview + JSON sidecar", run_render});
