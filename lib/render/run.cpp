#include "render/run.h"

#include <sstream>

#include <nlohmann/json.hpp>

#include "core/error.h"
#include "core/progress.h"
#include "render/image_io.h"
#include "render/path_tracer.h"

namespace vpm {

namespace {

nlohmann::json toml_to_json(const toml::table& table) {
    std::ostringstream s;
    s << toml::json_formatter(table);
    return nlohmann::json::parse(s.str());
}

}  // namespace

RunResult run_scene(const Scene& scene, const RunOptions& options) {
    RunResult result;
    result.record = RunRecord::with_environment();
    result.record.set("config", toml_to_json(scene.resolved));
    result.record.set("config_file", scene.source_file);
    result.record.set("seed", scene.render.seed);
    result.record.set("integrator", scene.render.integrator);
    result.record.set("build_log", scene.build_log);

    std::unique_ptr<Integrator> integrator;
    if (scene.render.integrator == "path") {
        integrator = std::make_unique<PathTracer>(scene);
    } else {
        throw Error("integrator '" + scene.render.integrator + "' is not available in this build");
    }

    RenderOptions ro;
    ro.width = scene.render.width;
    ro.height = scene.render.height;
    ro.spp = scene.render.spp;
    ro.seed = scene.render.seed;
    ro.progress = options.progress;
    ro.stream_offset = options.stream_offset;
    result.image = render_image(scene.camera, *integrator, ro, result.stats);
    result.record.phase("render", result.stats.seconds);
    result.record.set("render.samples", result.stats.samples);
    result.record.set("render.samples_per_second", result.stats.samples_per_second());
    result.record.set("render.nonfinite_samples", result.stats.nonfinite_samples);
    if (options.log) {
        *options.log << "render: " << ro.width << "x" << ro.height << " at " << ro.spp << " spp in "
                      << result.stats.seconds << " s (" << result.stats.samples_per_second() / 1e6
                      << " M samples/s)";
        if (result.stats.nonfinite_samples)
            *options.log << ", " << result.stats.nonfinite_samples << " non-finite samples left out";
        *options.log << "\n";
    }
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
