// vpm render CONFIG [-o OUT.exr] [--set KEY=VALUE]... [--threads N] [--quiet]
#include <iostream>

#include <CLI/CLI.hpp>
#include <tbb/global_control.h>
#include <tbb/info.h>

#include "command.h"
#include "core/progress.h"
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
    vpm::RunResult result = vpm::run(run_config, options);
    result.record.phase("load", load_seconds);
    result.record.set("threads", n_threads);
    std::vector<std::string> args(argv, argv + argc);
    result.record.set("command_line", args);
    vpm::write_run_outputs(render.output, result, render.exposure);
    if (log) *log << "wrote " << render.output << " (+ .png, .json)\n";
    return 0;
}

}  // namespace

VPM_REGISTER_COMMAND({"render", "render a scene config to EXR + PNG preview + JSON sidecar", run_render});
