#include "render/run/run.h"

#include <algorithm>
#include <cmath>
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
// Camera samples below which a pass is cheaper rendered together with the next ones: one go over
// the image costs a task launch, a progress bar and a pass over the pixel sums whatever it holds.
constexpr int64_t kMinGroupSamples = int64_t(1) << 16;

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
        const double pass_samples = double(rs.width) * double(rs.height) * double(spp);
        return integrator->stateless_passes() ? int64_t(std::min(65536.0, std::ceil(double(kMinGroupSamples) / pass_samples))) : 1;
    };
    // A time limit's passes: by the clock, or, given render.time_limit_passes (which a time-limited run's
    // record sets to the passes it took), exactly those, so that the record renders the same image. The
    // integrator plans for render.time_limit either way; only the count came from the clock.
    const bool clock_stops = rs.time_limit > 0 && rs.time_limit_passes == 0;
    const int64_t fixed_passes = rs.time_limit_passes > 0 ? rs.time_limit_passes : rs.passes;
    if (options.log && rs.time_limit_passes > 0)
        *options.log << "passes: " << rs.time_limit_passes << ", render.time_limit_passes (the count a render.time_limit = "
                     << rs.time_limit << " s run took, from its record), not the clock; --unset render.time_limit_passes "
                     << "renders to the clock\n";
    const Timer run_timer;
    // One bar for a run of several passes, against its passes or its time limit; the bars of a pass's
    // photons and rows then show on its first pass only (its one-off work), not restarting each pass.
    const bool several_passes = fixed_passes > 1 || clock_stops;
    Progress run_progress(clock_stops ? "time limit" : "passes",
                          clock_stops ? uint64_t(std::ceil(rs.time_limit * 1000.0)) : uint64_t(fixed_passes),
                          options.progress && several_passes,
                          clock_stops ? Progress::Unit::milliseconds : Progress::Unit::items);
    uint64_t progress_ms = 0;   // run_progress's count under the clock
    int64_t done = 0;   // passes rendered
    double first_group_seconds = 0.0;
    int64_t first_group_passes = 0;
    // Time per pass from the passes after the first group; until there are any, the first group's
    // whole time, or only its render where nothing else repeats (a stateless integrator: the photon
    // map planned without a map paid its photon pass and pilot once, and they would otherwise count as
    // every pass's cost).
    auto seconds_per_pass = [&] {
        if (done > first_group_passes) return (run_timer.seconds() - first_group_seconds) / double(done - first_group_passes);
        // (The first group's one-off work, the photon map's pilot, is not a pass's: counted as one it
        // would stop a run with half its time left.)
        return (integrator->stateless_passes() ? render.seconds : run_timer.seconds() - integrator->one_off_seconds()) /
               double(done);   // render: the first group's so far
    };
    for (;;) {
        const int64_t group = group_size();
        // How many passes this group renders: the configured ones first, then, under a time limit,
        // as many as the measured time per pass says still fit (at least one: the limit is checked
        // before a group starts). The image depends on the total pass count only.
        int64_t n = 1;
        if (done < fixed_passes) {
            n = std::min<int64_t>(group, fixed_passes - done);
        } else {
            const double per_pass = seconds_per_pass();
            const double fit = per_pass > 0.0 ? std::floor((rs.time_limit - run_timer.seconds()) / per_pass) : double(group);
            n = std::max<int64_t>(1, std::min<int64_t>(group, int64_t(std::min(fit, double(group)))));
            n = std::min<int64_t>(n, kMaxRunPasses - rs.first_pass - done);
        }
        const Timer group_timer;
        const double started = run_timer.seconds();
        const int index = int(rs.first_pass + done);   // the first pass's identity: its streams
        const uint64_t stream = options.stream_offset + uint64_t(index) * kPassStreamStride;
        PassContext context;
        context.seed = rs.seed;
        context.stream_offset = stream;
        context.run_stream_offset = options.stream_offset;
        context.pass = index;
        context.configured_spp = rs.spp_per_pass();
        context.first_of_run = done == 0;
        context.progress = options.progress && (!several_passes || done == 0);
        context.log = options.log;
        integrator->prepare(context, result.stats);
        spp = integrator->samples_per_pass(rs.spp_per_pass());

        RenderOptions ro;
        ro.width = rs.width;
        ro.height = rs.height;
        ro.spp = spp;
        ro.seed = rs.seed;
        ro.progress = options.progress && (!several_passes || done == 0);
        ro.stream_offset = stream;
        ro.sampler = rs.sampler;
        if (clock_stops && done == 0) {   // the first group: later ones are sized by the measured pass time
            ro.seconds_left = std::max(1e-9, rs.time_limit - run_timer.seconds());
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
        const int64_t before = done;
        done += n;
        const PassGroupStats this_group{done, n, spp, seconds, run_timer.seconds(), mean_of_means};
        if (clock_stops) {
            const uint64_t now_ms = uint64_t(run_timer.seconds() * 1000.0);
            if (now_ms > progress_ms) run_progress.advance(now_ms - progress_ms);
            progress_ms = std::max(progress_ms, now_ms);
        } else {
            run_progress.advance(uint64_t(n));
        }
        if (options.on_pass_group) options.on_pass_group(this_group);

        // Time per pass from the passes after the first: the first also holds one-off work (the
        // photon map's pilot, the light allocation) and would stop a time-limited run early.
        if (before == 0) {
            first_group_seconds = run_timer.seconds();
            first_group_passes = done;
        }
        const double mean_pass = seconds_per_pass();
        if (before == 0 && clock_stops && run_timer.seconds() > rs.time_limit) {
            std::ostringstream w;
            w << "render.time_limit = " << rs.time_limit << " s is shorter than the first " << (n > 1 ? "passes" : "pass")
              << " (" << run_timer.seconds() << " s): " << done << (done > 1 ? " passes" : " pass")
              << " written, at least render.passes = " << rs.passes;
            result.stats.warn(w.str(), options.log);
        }
        const bool more = (done < fixed_passes || (clock_stops && run_timer.seconds() + mean_pass <= rs.time_limit &&
                                                    done < kMaxRunPasses - rs.first_pass)) &&
                          !(options.cancelled && options.cancelled());
        if (options.on_pass || !more) {
            Image mean(rs.width, rs.height);
            for (size_t i = 0; i < sum.size(); ++i) mean.rgb[i] = float(sum[i] / double(done));   // exact for one pass
            if (options.on_pass) options.on_pass(mean, this_group);
            if (!more) result.image = std::move(mean);
        }
        if (!more && options.pass_variance && done > 1) {
            // From the pass sums in double: Y is linear, so the mean of the passes' luminances is the
            // luminance of the summed pixel.
            result.variance = Image(rs.width, rs.height);
            const double N = double(done);
            for (size_t p = 0; p < luminance_sq.size(); ++p) {
                const double y = (0.2126 * sum[3 * p] + 0.7152 * sum[3 * p + 1] + 0.0722 * sum[3 * p + 2]) / N;
                const double v = std::max(0.0, (luminance_sq[p] - N * y * y) / (N * (N - 1.0)));   // rounding only
                for (int c = 0; c < 3; ++c) result.variance.rgb[3 * p + size_t(c)] = float(v);
            }
        }
        // A line when the count passes 1, 2, 4, 8, ...: a time-limited run may make millions.
        auto bits = [](int64_t v) { return v > 0 ? 64 - __builtin_clzll(uint64_t(v)) : 0; };   // floor(log2 v) + 1
        if (options.log && (done > 1 || more) && bits(done) > bits(before))
            *options.log << "pass " << done << (clock_stops ? "" : "/" + std::to_string(fixed_passes)) << ": "
                         << each << " s each, " << run_timer.seconds() << " s elapsed\n";
        if (!more) break;
    }
    run_progress.done();
    if (options.log) {
        const uint64_t passes = result.stats.pass_count();
        *options.log << "render: " << rs.width << "x" << rs.height << " at "
                     << render.samples / (uint64_t(rs.width) * uint64_t(rs.height)) << " spp";
        if (passes > 1) *options.log << " in " << passes << " passes";
        *options.log << " in " << render.seconds << " s (" << render.samples_per_second() / 1e6 << " M samples/s)";
        if (render.nonfinite_samples) *options.log << ", " << render.nonfinite_samples << " non-finite samples left out";
        if (render.negative_samples) *options.log << ", " << render.negative_samples << " NEGATIVE samples (non-physical) kept";
        *options.log << "\n";
    }
    integrator->collect(result.stats, options.log);
    if (result.stats.integrator_used.empty()) result.stats.integrator_used = integrator->name();

    result.record = RunRecord::with_environment();
    result.record.set("config", toml_to_json(config.resolved));
    // What the document left unset, so that loading the record leaves it unset again (a default read
    // back as a value would pin what the plan chooses); and the passes a time limit took, so that the
    // record renders them again without the clock.
    std::vector<std::string> defaulted = config.defaulted;
    if (rs.time_limit > 0) {
        result.record.set("config.render.time_limit_passes", done);
        defaulted.erase(std::remove(defaulted.begin(), defaulted.end(), "render.time_limit_passes"), defaulted.end());
    }
    result.record.set("config_defaults", defaulted);
    result.record.set("config_file", config.source_file);
    result.record.set("seed", rs.seed);
    result.record.set("integrator", integrator->name());
    result.record.set("build_log", config.scene->build_log);
    write_run_stats(result.stats, result.record);
    return result;
}

}  // namespace vpm
