#pragma once
// The log lines of the automatic plan (auto_gather.cpp): the choice in one short line, one indented
// line per candidate with what the pilot measured, and the integrator's and the passes' choices.
#include <iosfwd>

#include "render/photon_map/photon_map_stats.h"

namespace vpm {

// What the log says beside the plan's own statistics.
struct AutoPlanReport {
    double pixels = 0.0;             // the image's pixels (a dropped candidate's pass cost)
    bool chosen_by_pilot = true;     // photons.gather = "auto" or the "auto" integrator, else measured to size passes
    bool chooses_integrator = false; // render.integrator = "auto"
    bool path_misses_light = false;  // render/plan/no_map_candidate.h: the path tracer cannot reach the light
    bool map_empty = false;          // the pilot's volume map holds no photon
    bool measured_by_pilot = true;   // false: an empty volume map beside a surface map, nothing measured
    bool no_map = false;             // the plan chose "continue": no photon pass from now on
    bool one_spp = false;            // the path tracer's passes of one sample under render.time_limit
};

void log_auto_plan(std::ostream& log, const AutoGatherStats& a, const AutoPlanReport& r);

}  // namespace vpm
