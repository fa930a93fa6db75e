// vpm render CONFIG [-o OUT.exr] [--set KEY=VALUE]... [--threads N] [--quiet]
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>

#include <CLI/CLI.hpp>
#include <tbb/global_control.h>
#include <tbb/info.h>

#include "arguments.h"
#include "command.h"
#include "core/sampling/sampler_registry.h"
#include "core/thread_limit.h"
#include "core/progress.h"
#include "analysis/metrics/error_metrics.h"
#include "analysis/metrics/reference_noise.h"
#include "config/unset_key.h"
#include "core/error.h"
#include "core/registry.h"
#include "photon/estimate/estimators.h"
#include "photon/estimate/kernels.h"
#include "render/run/image_io.h"
#include "render/integrator_registry.h"
#include "render/photon_map/gathers/gather_registry.h"
#include "render/photon_map/gathers/photon_beams_gather.h"
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
           "  photons.beam_widths " + registry_list(vpm::beam_widths_names()) + "\n"
           "  render.sampler     " + registry_list(vpm::sampler_names()) + "\n"
           "  photons.sampler    " + registry_list(vpm::sampler_names()) + "\n"
           "Camera paths at glass (photon map):\n"
           "  photons.glass_splits  0-4, default 2: at the first this many glass hits a camera path follows both the\n"
           "                        reflection (weight F) and the refraction (1 - F); 0: one chosen by Fresnel\n";
}

// Under render.time_limit, the automatic choices that keys the user set switch off
// (docs/integrator_choice.md, "What the plan chooses when a key is unset"), one line each, said
// before the work; "" when none.
std::string pinned_choices(const vpm::ConfigDocument& doc, const vpm::RenderSettings& render, const std::string& integrator) {
    if (!(render.time_limit > 0)) return "";
    auto set_at = [&](const std::string& table, const std::string& key) -> const toml::node* {
        const toml::table* t = doc.root.get_as<toml::table>(table);
        return t ? t->get(key) : nullptr;
    };
    std::ostringstream out;
    auto pin = [&](const std::string& table, const std::string& key, const std::string& switched_off) {
        const toml::node* v = set_at(table, key);
        if (!v || v->value<std::string>() == std::optional<std::string>("auto")) return;   // "auto" is the choice itself
        std::ostringstream value;
        v->visit([&](const auto& n) { value << n; });
        const std::string path = table + "." + key;
        out << "pin: " << path << " = " << value.str() << " ("
            << (doc.overridden.count(path) ? std::string("--set") : doc.file) << ") " << switched_off
            << "; --unset " << path << " lets it choose\n";
    };
    if (integrator == "photon_map" || integrator == "auto") {
        pin("photons", "count", "switches off the time limit's sizing of photons per pass");
        pin("render", "spp", "switches off the time limit's sizing of samples per pass");
        pin("render", "passes", "switches off the time limit's sizing of samples per pass");
        pin("photons", "gather", "switches off the pilot's choice of the gather");
    } else if (integrator == "path") {
        pin("render", "passes", "switches off the time limit's passes of one sample per pixel");
    }
    return out.str();
}

int run_render(int argc, char** argv) {
    CLI::App app("Render a scene config to an OpenEXR image, a PNG preview and a JSON sidecar.", "vpm render");
    app.footer(registered_names());
    std::string config, output;
    std::vector<std::string> sets;
    int threads = -1;
    bool quiet = false;
    app.add_option("config", config, "Scene config (TOML)")->required();
    CLI::Option* output_option = app.add_option("-o,--output", output, "Output EXR, name ending in .exr; OUT.png and OUT.json go beside it (default: render.output from the config, else out/render.exr)");
    app.add_option("--set", sets, "Override a config key by dotted path, e.g. media.0.sigma_t_scale=10 (repeatable)")
        ->allow_extra_args(false);   // one value per --set, so `--set k=v CONFIG` leaves CONFIG alone
    std::vector<std::string> unsets;
    app.add_option("--unset", unsets,
                   "Remove a key the config file sets, so its default or the automatic choice it pins applies again, "
                   "e.g. --unset photons.count under render.time_limit (repeatable; after every --set)")
        ->allow_extra_args(false);
    app.add_option("--threads", threads, "Worker threads (0: all cores; default: render.threads)")->check(CLI::Range(0, vpm::kMaxThreads));
    app.add_flag("-q,--quiet", quiet, "No progress bar or log on stderr");
    std::string reference;
    app.add_option("--reference", reference,
                   "Reference EXR: after every pass, write the error of the mean so far against it to OUT.passes.csv "
                   "(pass, spp, elapsed seconds, relative RMSE, relative mean error)")
        ->check(CLI::ExistingFile);
    std::string metric_text = "relmse";
    double epsilon = vpm::kDefaultMetricEpsilon;
    app.add_option("--metric", metric_text,
                   "With --reference: the named error in OUT.passes.csv beside the relative RMSE: relmse, relrmse or smape "
                   "(docs/metrics.md); REFERENCE.variance.exr beside the reference, when present, gives its noise floor, "
                   "which is subtracted")
        ->capture_default_str();
    app.add_option("--epsilon", epsilon, "With --metric relmse or smape: the denominator's eps")
        ->capture_default_str()
        ->check(vpm::cli::finite_in(1e-12, 1e12, "a number > 0"));
    bool variance = false;
    app.add_flag("--variance", variance,
                 "Also write OUT.variance.exr: each pixel's luminance variance as an estimate, from the spread of the "
                 "independent passes (needs two or more passes); vpm compare subtracts it as the reference's noise");
    if (!vpm::cli::parse_arguments(app, argc, argv)) return 0;
    if (output_option->count() > 0 && output.empty())
        throw vpm::cli::UsageError("-o: the output name is empty; give a file name ending in .exr (its .png and .json "
                                   "are written beside it), or leave -o out for render.output");
    vpm::MetricOptions metric;
    try {
        metric.metric = vpm::parse_error_metric(metric_text);
    } catch (const vpm::Error& e) {
        throw vpm::cli::UsageError(std::string("--metric: ") + e.what());
    }
    metric.epsilon = epsilon;

    // Command-line settings go through the same validation as the file and end up in the
    // resolved config, so the sidecar says exactly what ran.
    // They go first, so that an error in a user's --set is reported against that --set.
    std::vector<std::string> cli_sets;
    if (!output.empty()) cli_sets.push_back("render.output=" + toml_string(output));
    if (threads >= 0) cli_sets.push_back("render.threads=" + std::to_string(threads));
    sets.insert(sets.begin(), cli_sets.begin(), cli_sets.end());

    const vpm::Timer load_timer;
    const std::shared_ptr<vpm::ConfigDocument> doc = vpm::load_config(config, sets);
    for (const std::string& key : unsets) vpm::unset_key(*doc, key);
    const vpm::RunConfig run_config = vpm::RunConfig::build(doc);
    const vpm::RenderSettings& render = run_config.render;
    const double load_seconds = load_timer.seconds();
    if (variance && render.passes < 2 && render.time_limit <= 0)
        throw vpm::Error("--variance: needs two or more passes (the spread of independent passes), but render.passes = " +
                         std::to_string(render.passes) + " and no render.time_limit; set render.passes = 2 or more");
    const std::filesystem::path variance_path = vpm::variance_path_for(render.output);
    // Before the work: a run that cannot write its outputs fails now, not after the render.
    std::filesystem::path passes_path = render.output;
    passes_path.replace_extension(".passes.csv");
    // A run of more than one pass streams one row per pass to OUT.passes.csv (bounded memory).
    const bool passes_table = !reference.empty() || render.passes > 1 || render.time_limit > 0;
    std::vector<std::filesystem::path> extra_outputs;
    if (passes_table) extra_outputs.push_back(passes_path);
    if (variance) extra_outputs.push_back(variance_path);
    vpm::check_run_outputs(render.output, extra_outputs);
    const int n_threads = render.threads > 0 ? render.threads : tbb::info::default_concurrency();
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(n_threads));

    std::ostream* log = quiet ? nullptr : &std::cerr;
    if (log) {
        *log << "load: " << config << " in " << load_seconds << " s, " << n_threads << " threads\n";
        for (const auto& line : run_config.scene->build_log) *log << "  " << line << "\n";
        if (const std::string pins = pinned_choices(*doc, render, run_config.integrator->name); !pins.empty()) *log << pins;
    }
    vpm::RunOptions options;
    options.progress = !quiet;
    options.log = log;
    options.pass_variance = variance;
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
        const std::string m = vpm::metric_name(metric.metric);
        passes_csv << "pass,spp,elapsed_s,seconds,passes,image_mean"
                   << (reference.empty() ? "" : ",rel_rmse,rel_mean_error," + m + "," + m + "_noise_floor") << '\n';
    }
    vpm::RunError last_error;
    vpm::MetricValue last_metric;
    std::string noise_source;
    if (!reference.empty()) {
        const vpm::NoisyReference noisy = vpm::load_reference(reference);
        const vpm::Image& ref = noisy.image;
        noise_source = noisy.noise_source;
        const std::optional<vpm::Image> ref_variance = noisy.variance;
        if (ref.width != render.width || ref.height != render.height)
            throw vpm::Error(reference + ": reference is " + std::to_string(ref.width) + "x" + std::to_string(ref.height) +
                             ", the render " + std::to_string(render.width) + "x" + std::to_string(render.height));
        // Before the work, naming the file: errors are relative to the reference's mean luminance.
        try {
            vpm::reference_scale(ref);
        } catch (const vpm::Error& e) {
            throw vpm::Error(reference + ": --reference: " + e.what());
        }
        options.on_pass = [&, ref, ref_variance](const vpm::Image& mean, const vpm::PassGroupStats& p) {
            last_error = vpm::run_error(mean, ref);
            last_metric = vpm::measure_error(mean, ref, metric, ref_variance ? &*ref_variance : nullptr);
            pass_row(p);
            passes_csv << ',' << last_error.rel_rmse << ',' << last_error.rel_mean_error << ',' << last_metric.value << ','
                       << last_metric.floor << '\n';
        };
        if (log)
            *log << "error against " << reference << ": " << vpm::metric_formula(metric.metric, metric.epsilon) << "; "
                 << (noisy.variance ? "reference noise from " + noise_source + ", subtracted"
                                    : "reference noise unknown (no " + vpm::variance_path_for(reference).string() +
                                          "): not subtracted")
                 << "\n";
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
        result.record.set("reference.metric", vpm::metric_name(metric.metric));
        result.record.set("reference.metric_formula", vpm::metric_formula(metric.metric, metric.epsilon));
        result.record.set("reference.error", last_metric.value);
        result.record.set("reference.error_raw", last_metric.raw);
        if (last_metric.floor_known()) result.record.set("reference.noise_floor", last_metric.floor);
        result.record.set("reference.noise_source", noise_source);
    }
    // The variance image is one of the run's files, committed with the others; a run that made one
    // pass has none.
    const bool variance_written = variance && result.variance.width > 0;
    if (variance_written) {
        staged.push_back(vpm::stage_exr(variance_path, result.variance));
        result.record.set("variance_file", variance_path.string());
    } else if (variance) {
        std::cerr << "vpm render: warning: --variance: one pass ran (render.time_limit = " << render.time_limit
                  << " s), so there is no spread to measure; " << variance_path.string() << " is not written\n";
    }
    result.record.phase("load", load_seconds);
    result.record.set("threads", n_threads);
    std::vector<std::string> args(argv, argv + argc);
    result.record.set("command_line", args);
    // The passes table is one of the run's files: committed together with the image and sidecar.
    if (passes_table) {
        passes_csv.close();
        if (!passes_csv) staged.front().abort("writing the passes table failed (disk full?)");
    }
    vpm::write_run_outputs(render.output, result, render.exposure, {}, std::move(staged));
    // A variance image from an earlier render to the same OUT would pass for this run's noise.
    if (!variance_written && std::filesystem::exists(variance_path)) {
        std::error_code ec;
        std::filesystem::remove(variance_path, ec);
        if (log) *log << "removed " << variance_path.string() << ": it belonged to an earlier render to " << render.output << "\n";
    }
    if (!reference.empty() && log)
        *log << "error against " << reference << ": " << vpm::describe(last_metric) << ", rel RMSE " << last_error.rel_rmse
             << " after " << result.stats.pass_count() << " pass(es)\n";
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
