// vpm render CONFIG [-o OUT.exr] [--set KEY=VALUE]... [--threads N] [--quiet]
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include <CLI/CLI.hpp>
#include <tbb/global_control.h>
#include <tbb/info.h>

#include "arguments.h"
#include "command.h"
#include "core/sampler_registry.h"
#include "core/thread_limit.h"
#include "core/progress.h"
#include "analysis/error_metrics.h"
#include "core/error.h"
#include "core/registry.h"
#include "photon/estimate/estimators.h"
#include "photon/estimate/kernels.h"
#include "render/run/image_io.h"
#include "render/integrator_registry.h"
#include "render/photon_map/gathers/gather_registry.h"
#include "render/run/run.h"
#include "render/run/run_outputs.h"
#include "render/run/staged_file.h"
#include "scene/lights/light_registry.h"
#include "scene/media/medium_registry.h"
#include "scene/materials/material_registry.h"

namespace {

// A TOML basic string: quotes and backslashes in a path must not end the string early.
std::string toml_string(const std::string& s) {
    std::string q = "\"";
    for (char c : s) {
        if (c == '"' || c == '\\') q += '\\';
        q += c;
    }
    return q + "\"";
}

// The names users choose from, read from the registries so that --help cannot drift from them.
std::string registered_names() {
    using vpm::registry_list;
    return "Registered names (docs/config.md lists the keys of each):\n"
           "  render.integrator  " + registry_list(vpm::integrator_names()) + "\n"
           "  lights.N.type      " + registry_list(vpm::light_names()) + "\n"
           "  media.N.type       " + registry_list(vpm::medium_names()) + "\n"
           "  shapes.N.material  " + registry_list(vpm::material_names()) + "\n"
           "  photons.estimator  " + registry_list(vpm::Estimator::names()) + "\n"
           "  photons.kernel     " + registry_list(vpm::Kernel::names()) + "\n"
           "  photons.gather     " + registry_list(vpm::gather_names()) + "\n"
           "  render.sampler     " + registry_list(vpm::sampler_names()) + "\n"
           "  photons.sampler    " + registry_list(vpm::sampler_names()) + "\n";
}

int run_render(int argc, char** argv) {
    CLI::App app("Render a scene config to an OpenEXR image, a PNG preview and a JSON sidecar.", "vpm render");
    app.footer(registered_names());
    std::string config, output;
    std::vector<std::string> sets;
    int threads = -1;
    bool quiet = false;
    app.add_option("config", config, "Scene config (TOML)")->required();
    app.add_option("-o,--output", output, "Output EXR, name ending in .exr; OUT.png and OUT.json go beside it (default: render.output from the config, else out/render.exr)");
    app.add_option("--set", sets, "Override a config key by dotted path, e.g. media.0.sigma_t_scale=10 (repeatable)")
        ->allow_extra_args(false);   // one value per --set, so `--set k=v CONFIG` leaves CONFIG alone
    app.add_option("--threads", threads, "Worker threads (0: all cores; default: render.threads)")->check(CLI::Range(0, vpm::kMaxThreads));
    app.add_flag("-q,--quiet", quiet, "No progress bar or log on stderr");
    std::string reference;
    app.add_option("--reference", reference,
                   "Reference EXR: after every pass, write the error of the mean so far against it to OUT.passes.csv "
                   "(pass, spp, elapsed seconds, relative RMSE, relative mean error)")
        ->check(CLI::ExistingFile);
    if (!vpm::cli::parse_arguments(app, argc, argv)) return 0;

    // Command-line settings go through the same validation as the file and end up in the
    // resolved config, so the sidecar says exactly what ran.
    // They go first, so that an error in a user's --set is reported against that --set.
    std::vector<std::string> cli_sets;
    if (!output.empty()) cli_sets.push_back("render.output=" + toml_string(output));
    if (threads >= 0) cli_sets.push_back("render.threads=" + std::to_string(threads));
    sets.insert(sets.begin(), cli_sets.begin(), cli_sets.end());

    const vpm::Timer load_timer;
    const vpm::RunConfig run_config = vpm::RunConfig::load(config, sets);
    const vpm::RenderSettings& render = run_config.render;
    const double load_seconds = load_timer.seconds();
    // Before the work: a run that cannot write its outputs fails now, not after the render.
    std::filesystem::path passes_path = render.output;
    passes_path.replace_extension(".passes.csv");
    // A run of more than one pass streams one row per pass to OUT.passes.csv (bounded memory).
    const bool passes_table = !reference.empty() || render.passes > 1 || render.time_limit > 0;
    if (passes_table) vpm::check_run_outputs(render.output, {passes_path});
    else vpm::check_run_outputs(render.output);
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
    // One row per group of passes rendered together (one pass for the photon map: run.h), written to the table's staged
    // temporary as the run goes (a time-limited run may make millions of passes: nothing per pass
    // stays in memory) and committed with the other files.
    std::vector<vpm::StagedFile> staged;
    std::ofstream passes_csv;
    auto pass_row = [&](const vpm::PassGroupStats& p) {
        passes_csv << p.passes_done << ',' << p.passes_done * p.spp << ',' << p.elapsed << ',' << p.seconds << ','
                   << p.passes << ',' << p.image_mean;
    };
    if (passes_table) {
        staged.emplace_back(passes_path);
        passes_csv.open(staged.back().temp());
        if (!passes_csv) staged.back().abort("cannot create the temporary " + staged.back().temp().string());
        passes_csv.precision(9);
        passes_csv << "pass,spp,elapsed_s,seconds,passes,image_mean" << (reference.empty() ? "" : ",rel_rmse,rel_mean_error") << '\n';
    }
    vpm::RunError last_error;
    if (!reference.empty()) {
        const vpm::Image ref = vpm::read_exr(reference);
        if (ref.width != render.width || ref.height != render.height)
            throw vpm::Error(reference + ": reference is " + std::to_string(ref.width) + "x" + std::to_string(ref.height) +
                             ", the render " + std::to_string(render.width) + "x" + std::to_string(render.height));
        // Before the work, naming the file: errors are relative to the reference's mean luminance.
        try {
            vpm::reference_scale(ref);
        } catch (const vpm::Error& e) {
            throw vpm::Error(reference + ": --reference: " + e.what());
        }
        options.on_pass = [&, ref](const vpm::Image& mean, const vpm::PassGroupStats& p) {
            last_error = vpm::run_error(mean, ref);
            pass_row(p);
            passes_csv << ',' << last_error.rel_rmse << ',' << last_error.rel_mean_error << '\n';
        };
    } else if (passes_table) {
        options.on_pass_group = [&](const vpm::PassGroupStats& p) {
            pass_row(p);
            passes_csv << '\n';
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
    // The passes table is one of the run's files: committed together with the image and sidecar.
    if (passes_table) {
        passes_csv.close();
        if (!passes_csv) staged.back().abort("writing the passes table failed (disk full?)");
    }
    vpm::write_run_outputs(render.output, result, render.exposure, {}, std::move(staged));
    if (!reference.empty() && log)
        *log << "error against " << reference << ": rel RMSE " << last_error.rel_rmse << " after "
             << result.stats.pass_count() << " pass(es)\n";
    if (passes_table && log) *log << "per pass: " << passes_path.string() << "\n";
    if (log) *log << "wrote " << render.output << " (+ .png, .json)\n";
    if (const size_t bad = vpm::count_nonfinite_pixels(result.image))
        std::cerr << "vpm render: warning: " << bad << " of " << size_t(result.image.width) * size_t(result.image.height)
                  << " pixels are NaN or Inf (render.nonfinite_pixels in " << vpm::sidecar_path_for(render.output).string()
                  << ")\n";
    if (const size_t negative = vpm::count_negative_pixels(result.image))
        std::cerr << "vpm render: warning: " << negative << " of " << size_t(result.image.width) * size_t(result.image.height)
                  << " pixels are negative, which no radiance is (render.negative_pixels in "
                  << vpm::sidecar_path_for(render.output).string() << ")\n";
    return 0;
}

}  // namespace

VPM_REGISTER_COMMAND({"render", "render a scene config to EXR + PNG preview + JSON sidecar", run_render});
