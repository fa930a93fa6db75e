#pragma once
// How many passes a run renders, and in which groups: the configured render.passes, or under
// render.time_limit as many as the measured time per pass says still fit (render.time_limit_passes,
// which a time-limited run's record sets, replaces the clock by that count so the record renders
// the same image). The image depends on the total pass count only, never on the grouping.
#include <cstdint>

#include "core/progress.h"
#include "render/integrator.h"
#include "render/run/render_loop.h"
#include "render/run/render_settings.h"

namespace vpm {

class PassBudget {
public:
    // `render` is the run's camera-pass statistics as they accumulate (its seconds serve the first
    // group's time per pass of a stateless integrator).
    PassBudget(const RenderSettings& settings, const Integrator& integrator, const RenderStats& render);

    bool clock_stops() const { return clock_stops_; }      // a time limit decides the count, by the clock
    int64_t fixed_passes() const { return fixed_passes_; }   // passes rendered before the clock is asked
    int64_t done() const { return done_; }
    double elapsed() const { return timer_.seconds(); }

    // Passes the next group renders: the configured ones first (at most `group`), then as many of `group`
    // as fit in the time left (at least one: the limit is checked before a group starts).
    int64_t next_group(int64_t group) const;
    // Records a rendered group of n passes.
    void finished(int64_t n);
    // Whether another group fits: passes configured and not yet rendered, or time left for one more pass.
    bool more() const;
    // The first group ran past the time limit on its own.
    bool first_group_overran() const { return clock_stops_ && done_ == first_group_passes_ && timer_.seconds() > settings_.time_limit; }

private:
    // Time per pass from the passes after the first group; until there are any, the first group's
    // whole time, or only its render where nothing else repeats (a stateless integrator: the photon
    // map planned without a map paid its photon pass and pilot once, and they would otherwise count as
    // every pass's cost). The first group's one-off work, the photon map's pilot, is not a pass's:
    // counted as one it would stop a run with half its time left.
    double seconds_per_pass() const;

    const RenderSettings& settings_;
    const Integrator& integrator_;
    const RenderStats& render_;
    const Timer timer_;
    bool clock_stops_;
    int64_t fixed_passes_;
    int64_t done_ = 0;
    double first_group_seconds_ = 0.0;
    int64_t first_group_passes_ = 0;
};

}  // namespace vpm
