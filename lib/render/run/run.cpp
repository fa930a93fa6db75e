#include "render/run/run.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <nlohmann/json.hpp>

#include "core/error.h"
#include "core/progress.h"
#include "render/run/pass_budget.h"

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
// Camera samples below which a pass is cheaper rendered together with the next ones: one go over
// the image costs a task launch, a progress bar and a pass over the pixel sums whatever it holds.
constexpr int64_t kMinGroupSamples = int64_t(1) << 16;

// The pixel sums of the passes rendered so far as their mean image (exact for one pass).
Image mean_image(const std::vector<double>& sum, int width, int height, int64_t passes) {
    Image mean(width, height);
    for (size_t i = 0; i < sum.size(); ++i) mean.rgb[i] = float(sum[i] / double(passes));
    return mean;
}

// Per pixel, the variance of the image's luminance over `passes` passes, from the pass sums in double
// and the sums of the passes' squared luminances: Y is linear, so the mean of the passes' luminances is
// the luminance of the summed pixel.
Image pass_variance_image(const std::vector<double>& sum, const std::vector<double>& luminance_sq, int width,
                          int height, int64_t passes) {
    Image variance(width, height);
    const double N = double(passes);
    for (size_t p = 0; p < luminance_sq.size(); ++p) {
        const double y = (0.2126 * sum[3 * p] + 0.7152 * sum[3 * p + 1] + 0.0722 * sum[3 * p + 2]) / N;
        const double v = std::max(0.0, (luminance_sq[p] - N * y * y) / (N * (N - 1.0)));   // rounding only
        for (int c = 0; c < 3; ++c) variance.rgb[3 * p + size_t(c)] = float(v);
    }
    return variance;
}

// One bar for a run of several passes, against its passes or its time limit; the bars of a pass's
// photons and rows then show on its first pass only (its one-off work), not restarting each pass.
class RunProgress {
public:
    RunProgress(const PassBudget& budget, const RenderSettings& rs, bool shown)
        : budget_(budget),
          bar_(budget.clock_stops() ? "time limit" : "passes",
               budget.clock_stops() ? uint64_t(std::ceil(rs.time_limit * 1000.0)) : uint64_t(budget.fixed_passes()), shown,
               budget.clock_stops() ? Progress::Unit::milliseconds : Progress::Unit::items) {}
    void advance(int64_t passes) {
        if (!budget_.clock_stops()) return bar_.advance(uint64_t(passes));
        const uint64_t now_ms = uint64_t(budget_.elapsed() * 1000.0);
        if (now_ms > ms_) bar_.advance(now_ms - ms_);
        ms_ = std::max(ms_, now_ms);
    }
    void done() { bar_.done(); }

private:
    const PassBudget& budget_;
    Progress bar_;
    uint64_t ms_ = 0;   // the bar's count under the clock
};

// What a pass group's integrator and camera pass are told: its first pass's identity and streams.
PassContext pass_context(const RenderSettings& rs, const RunOptions& options, int index, uint64_t stream, bool first,
                         bool progress) {
    PassContext context;
    context.seed = rs.seed;
    context.stream_offset = stream;
    context.run_stream_offset = options.stream_offset;
    context.pass = index;
    context.configured_spp = rs.spp_per_pass();
    context.first_of_run = first;
    context.progress = progress;
    context.log = options.log;
    return context;
}

void log_render_summary(const RenderSettings& rs, const RunStats& stats, std::ostream& log) {
    const RenderStats& render = stats.render;
    const uint64_t passes = stats.pass_count();
    log << "render: " << rs.width << "x" << rs.height << " at " << render.samples / (uint64_t(rs.width) * uint64_t(rs.height))
        << " spp";
    if (passes > 1) log << " in " << passes << " passes";
    log << " in " << render.seconds << " s (" << render.samples_per_second() / 1e6 << " M samples/s)";
    if (render.nonfinite_samples) log << ", " << render.nonfinite_samples << " non-finite samples left out";
    if (render.negative_samples) log << ", " << render.negative_samples << " NEGATIVE samples (non-physical) kept";
    log << "\n";
}

// The run's record: the environment, the resolved config and what the document left unset (so that
// loading the record leaves it unset again: a default read back as a value would pin what the plan
// chooses), the passes a time limit took (so that the record renders them again without the clock),
// and the statistics.
RunRecord run_record(const RunConfig& config, const Integrator& integrator, const RunStats& stats, int64_t passes) {
    RunRecord record = RunRecord::with_environment();
    record.set("config", toml_to_json(config.resolved));
    std::vector<std::string> defaulted = config.defaulted;
    if (config.render.time_limit > 0) {
        record.set("config.render.time_limit_passes", passes);
        defaulted.erase(std::remove(defaulted.begin(), defaulted.end(), "render.time_limit_passes"), defaulted.end());
    }
    record.set("config_defaults", defaulted);
    record.set("config_file", config.source_file);
    record.set("seed", config.render.seed);
    record.set("integrator", integrator.name());
    record.set("build_log", config.scene->build_log);
    write_run_stats(stats, record);
    return record;
}

// A group of passes' render options from the render settings: image, crop, seed and sampler.
RenderOptions group_options(const RenderSettings& rs, int spp, uint64_t stream, bool progress) {
    RenderOptions ro;
    ro.width = rs.width;
    ro.height = rs.height;
    ro.spp = spp;
    ro.seed = rs.seed;
    ro.progress = progress;
    ro.stream_offset = stream;
    ro.sampler = rs.sampler;
    ro.crop_x0 = rs.crop_x0;
    ro.crop_y0 = rs.crop_y0;
    ro.crop_x1 = rs.crop_x1;
    ro.crop_y1 = rs.crop_y1;
    return ro;
}

}  // namespace

RunResult run(const RunConfig& config, const RunOptions& options) {
    RunResult result;
    const RenderSettings& rs = config.render;
    std::unique_ptr<Integrator> integrator = config.create_integrator();
    RenderStats& render = result.stats.render;
    // Pass values summed per pixel (3 doubles per pixel: RenderSettings::read checks they fit).
    std::vector<double> sum(size_t(rs.width) * size_t(rs.height) * 3, 0.0);
    std::vector<double> means;
    std::vector<double> luminance_sq(options.pass_variance ? size_t(rs.width) * size_t(rs.height) : 0, 0.0);
    result.stats.first_pass = rs.first_pass;
    int spp = rs.spp_per_pass();   // the integrator may size it (samples_per_pass) once prepared
    // Passes of an integrator without per-pass state go in groups of at least kMinGroupSamples
    // camera samples, rendered in one go over the image (render_passes: the same image as one by one).
    // (Asked per group: an integrator may become stateless once prepared, the photon map without a map.)
    auto group_size = [&] {
        const double pass_samples = rs.rendered_pixels() * double(spp);
        return integrator->stateless_passes() ? int64_t(std::min(65536.0, std::ceil(double(kMinGroupSamples) / pass_samples))) : 1;
    };
    if (options.log && rs.time_limit_passes > 0)
        *options.log << "passes: " << rs.time_limit_passes << ", render.time_limit_passes (the count a render.time_limit = "
                     << rs.time_limit << " s run took, from its record), not the clock; --unset render.time_limit_passes "
                     << "renders to the clock\n";
    PassBudget budget(rs, *integrator, render);
    const bool several_passes = budget.fixed_passes() > 1 || budget.clock_stops();
    RunProgress run_progress(budget, rs, options.progress && several_passes);
    for (;;) {
        const int64_t n = budget.next_group(group_size());
        const Timer group_timer;
        const double started = budget.elapsed();
        const int64_t before = budget.done();
        const int index = int(rs.first_pass + before);   // the first pass's identity: its streams
        const uint64_t stream = options.stream_offset + uint64_t(index) * kPassStreamStride;
        const bool progress = options.progress && (!several_passes || before == 0);
        integrator->prepare(pass_context(rs, options, index, stream, before == 0, progress), result.stats);
        spp = integrator->samples_per_pass(rs.spp_per_pass());

        RenderOptions ro = group_options(rs, spp, stream, progress);
        if (budget.clock_stops() && before == 0) {   // the first group: later ones are sized by the measured pass time
            ro.seconds_left = std::max(1e-9, rs.time_limit - budget.elapsed());
            ro.time_limit = rs.time_limit;
            ro.log = options.log;
        }
        RenderStats group_render;
        render_passes(config.scene->camera, *integrator, ro, int(n), kPassStreamStride, sum, means, group_render,
                      options.pass_variance ? &luminance_sq : nullptr);
        result.stats.phase("render", group_render.seconds);
        render.samples += group_render.samples;
        render.nonfinite_samples += group_render.nonfinite_samples;
        render.negative_samples += group_render.negative_samples;
        render.seconds += group_render.seconds;
        const double seconds = group_timer.seconds(), each = seconds / double(n);
        double mean_of_means = 0.0;
        for (int64_t g = 0; g < n; ++g) {
            result.stats.add_pass({each, started + each * double(g + 1), spp, means[size_t(g)]});
            mean_of_means += means[size_t(g)] / double(n);
        }
        budget.finished(n);
        const int64_t done = budget.done();
        const PassGroupStats this_group{done, n, spp, seconds, budget.elapsed(), mean_of_means};
        run_progress.advance(n);
        if (options.on_pass_group) options.on_pass_group(this_group);

        if (before == 0 && budget.first_group_overran()) {
            std::ostringstream w;
            w << "render.time_limit = " << rs.time_limit << " s is shorter than the first " << (n > 1 ? "passes" : "pass")
              << " (" << budget.elapsed() << " s): " << done << (done > 1 ? " passes" : " pass")
              << " written, at least render.passes = " << rs.passes;
            result.stats.warn(w.str(), options.log);
        }
        const bool more = budget.more() && !(options.cancelled && options.cancelled());
        if (options.on_pass || !more) {
            Image mean = mean_image(sum, rs.width, rs.height, done);
            if (options.on_pass) options.on_pass(mean, this_group);
            if (!more) result.image = std::move(mean);
        }
        if (!more && options.pass_variance && done > 1)
            result.variance = pass_variance_image(sum, luminance_sq, rs.width, rs.height, done);
        // A line when the count passes 1, 2, 4, 8, ...: a time-limited run may make millions.
        auto bits = [](int64_t v) { return v > 0 ? 64 - __builtin_clzll(uint64_t(v)) : 0; };   // floor(log2 v) + 1
        if (options.log && (done > 1 || more) && bits(done) > bits(before))
            *options.log << "pass " << done << (budget.clock_stops() ? "" : "/" + std::to_string(budget.fixed_passes()))
                         << ": " << each << " s each, " << budget.elapsed() << " s elapsed\n";
        if (!more) break;
    }
    run_progress.done();
    if (options.log) log_render_summary(rs, result.stats, *options.log);
    integrator->collect(result.stats, options.log);
    if (result.stats.integrator_used.empty()) result.stats.integrator_used = integrator->name();
    result.record = run_record(config, *integrator, result.stats, budget.done());
    return result;
}

}  // namespace vpm
