#include "render/run.h"

#include <sstream>

#include <nlohmann/json.hpp>

#include "core/error.h"
#include "core/progress.h"
#include "render/image_io.h"

namespace vpm {

namespace {

nlohmann::json toml_to_json(const toml::table& table) {
    std::ostringstream s;
    s << toml::json_formatter(table);
    return nlohmann::json::parse(s.str());
}

}  // namespace

RunResult run(const RunConfig& config, const RunOptions& options) {
    RunResult result;
    const RenderSettings& rs = config.render;
    std::unique_ptr<Integrator> integrator = config.create_integrator();
    PassContext context;
    context.seed = rs.seed;
    context.stream_offset = options.stream_offset;
    context.progress = options.progress;
    context.log = options.log;
    integrator->prepare(context, result.stats);

    RenderOptions ro;
    ro.width = rs.width;
    ro.height = rs.height;
    ro.spp = rs.spp;
    ro.seed = rs.seed;
    ro.progress = options.progress;
    ro.stream_offset = options.stream_offset;
    RenderStats& render = result.stats.render;
    result.image = render_image(config.scene->camera, *integrator, ro, render);
    result.stats.phase("render", render.seconds);
    if (options.log) {
        *options.log << "render: " << ro.width << "x" << ro.height << " at " << ro.spp << " spp in " << render.seconds
                     << " s (" << render.samples_per_second() / 1e6 << " M samples/s)";
        if (render.nonfinite_samples) *options.log << ", " << render.nonfinite_samples << " non-finite samples left out";
        *options.log << "\n";
    }
    integrator->collect(result.stats, options.log);

    result.record = RunRecord::with_environment();
    result.record.set("config", toml_to_json(config.resolved));
    result.record.set("config_file", config.source_file);
    result.record.set("seed", rs.seed);
    result.record.set("integrator", integrator->name());
    result.record.set("build_log", config.scene->build_log);
    write_run_stats(result.stats, result.record);
    return result;
}

void write_run_outputs(const std::filesystem::path& output, RunResult& result, double exposure) {
    const auto folder = output.has_parent_path() ? output.parent_path() : std::filesystem::path(".");
    std::error_code ec;
    std::filesystem::create_directories(folder, ec);
    if (ec) throw FileError(folder.string() + ": cannot create output folder: " + ec.message());
    const Timer timer;
    write_exr(output, result.image);
    write_png_preview(preview_path_for(output), result.image, exposure);
    result.record.phase("write", timer.seconds());
    result.record.set("output.exr", output.string());
    result.record.set("output.png", preview_path_for(output).string());
    result.record.write(sidecar_path_for(output));
}

}  // namespace vpm
