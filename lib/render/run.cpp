#include "render/run.h"

#include <sstream>

#include <nlohmann/json.hpp>

#include "core/error.h"
#include "core/progress.h"

namespace vpm {

namespace {

nlohmann::json toml_to_json(const toml::table& table) {
    std::ostringstream s;
    s << toml::json_formatter(table);
    return nlohmann::json::parse(s.str());
}

// Streams of pass p of a run with stream offset r: pass 0 keeps r (a one-pass run is what it always
// was); later passes sit 2^20 offsets apart so that repeats (consecutive r) never share a pass.
constexpr uint64_t kPassStreamStride = uint64_t(1) << 20;

}  // namespace

RunResult run(const RunConfig& config, const RunOptions& options) {
    RunResult result;
    const RenderSettings& rs = config.render;
    std::unique_ptr<Integrator> integrator = config.create_integrator();
    RenderStats& render = result.stats.render;
    std::vector<double> sum;   // pass images summed, for more than one pass
    result.stats.first_pass = rs.first_pass;
    const Timer run_timer;
    for (int pass = 0;; ++pass) {
        const Timer pass_timer;
        const int index = rs.first_pass + pass;   // the pass's identity: its streams
        const uint64_t stream = options.stream_offset + uint64_t(index) * kPassStreamStride;
        PassContext context;
        context.seed = rs.seed;
        context.stream_offset = stream;
        context.run_stream_offset = options.stream_offset;
        context.pass = index;
        context.first_of_run = pass == 0;
        context.progress = options.progress;
        context.log = options.log;
        integrator->prepare(context, result.stats);

        RenderOptions ro;
        ro.width = rs.width;
        ro.height = rs.height;
        ro.spp = rs.spp_per_pass();
        ro.seed = rs.seed;
        ro.progress = options.progress;
        ro.stream_offset = stream;
        RenderStats pass_render;
        Image image = render_image(config.scene->camera, *integrator, ro, pass_render);
        result.stats.phase("render", pass_render.seconds);
        render.samples += pass_render.samples;
        render.nonfinite_samples += pass_render.nonfinite_samples;
        render.seconds += pass_render.seconds;
        result.stats.passes.push_back({pass_timer.seconds(), run_timer.seconds(), ro.spp, image.mean()});

        const int done = pass + 1;
        const double mean_pass = run_timer.seconds() / done;
        const bool more = (done < rs.passes || (rs.time_limit > 0 && run_timer.seconds() + mean_pass <= rs.time_limit)) &&
                          !(options.cancelled && options.cancelled());
        if (done == 1 && !more) {
            result.image = std::move(image);   // one pass: the image as rendered
            if (options.on_pass) options.on_pass(result.image, result.stats.passes.back());
            break;
        }
        if (sum.empty()) sum.assign(image.rgb.size(), 0.0);
        for (size_t i = 0; i < sum.size(); ++i) sum[i] += double(image.rgb[i]);
        if (options.on_pass) {
            Image mean(rs.width, rs.height);
            for (size_t i = 0; i < sum.size(); ++i) mean.rgb[i] = float(sum[i] / double(done));
            options.on_pass(mean, result.stats.passes.back());
        }
        if (options.log)
            *options.log << "pass " << done << (rs.time_limit > 0 ? "" : "/" + std::to_string(rs.passes)) << ": "
                         << pass_timer.seconds() << " s, " << run_timer.seconds() << " s elapsed\n";
        if (!more) {
            result.image = Image(rs.width, rs.height);
            for (size_t i = 0; i < sum.size(); ++i) result.image.rgb[i] = float(sum[i] / double(done));
            break;
        }
    }
    if (options.log) {
        *options.log << "render: " << rs.width << "x" << rs.height << " at " << rs.spp_per_pass() * result.stats.passes.size()
                     << " spp";
        if (result.stats.passes.size() > 1) *options.log << " in " << result.stats.passes.size() << " passes";
        *options.log << " in " << render.seconds << " s (" << render.samples_per_second() / 1e6 << " M samples/s)";
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

}  // namespace vpm
