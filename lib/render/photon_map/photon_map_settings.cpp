#include "render/photon_map/photon_map_settings.h"

#include <algorithm>
#include <cmath>
#include <iostream>

#include "config/params.h"
#include "photon/estimate/radius_schedule.h"
#include "core/sampling/sampler_registry.h"
#include "render/photon_map/gathers/photon_beams_gather.h"

namespace vpm {

namespace {

// photons.gather from the gather registry (render/photon_map/gathers/gather_registry.h); an old name
// is accepted with a note on stderr.
GatherMode read_gather(Params& p, GatherMode fallback) {
    std::vector<std::pair<std::string, GatherMode>> allowed;
    for (const GatherEntry& e : gather_entries()) allowed.emplace_back(e.name, e.mode);
    for (const GatherAlias& a : gather_aliases()) allowed.emplace_back(a.name, a.mode);
    if (const toml::node* g = p.node("gather"))
        for (const GatherAlias& a : gather_aliases())
            if (g->value<std::string>().value_or("") == a.name) std::cerr << "note: " << p.where("gather") << ": " << a.note << "\n";
    return p.choice("gather", fallback, allowed);
}

// A number in (0, 1] or "auto" (photon/trace/store_thinning.h).
void read_store_probability(Params& p, PhotonMapSettings& s) {
    const char* key = "store_probability";
    const char* allowed = "must be a number in (0, 1] or \"auto\" (the probability from the walks' own statistics)";
    const toml::node* n = p.node(key);
    if (!n) {
        s.store_probability = p.real(key, s.store_probability);   // the default, into the resolved config
        return;
    }
    if (n->is_string()) {
        if (n->value<std::string>().value_or("") != "auto") p.fail(key, allowed);
        p.choice(key, "auto", {"auto"});
        s.store_auto = true;
        return;
    }
    const Range range{0.0, 1.0, true, false};
    if (!n->is_number() || !range.contains(n->value<double>().value_or(-1.0))) p.fail(key, allowed);
    s.store_probability = p.real(key, s.store_probability, range);
}

// photons.neighbours = "walks" is honoured or refused: the walk forms of classic and corrected
// (photon/estimate/walk_estimate.h), in the kNN photon estimates (not the beam gathers), and not on
// top of leave_group_out, which treats the same correlation another way.
void check_walk_neighbours(Params& p, const PhotonMapSettings& s) {
    if (s.neighbourhood != Neighbourhood::walks) return;
    const std::string name = s.estimator.name();
    if (name != "classic" && name != "corrected")
        p.fail("neighbours", "\"walks\" applies to photons.estimator = \"classic\" or \"corrected\" (got \"" + name +
                                 "\"); set photons.neighbours = \"photons\" or change the estimator");
    if (s.clustering == Clustering::leave_group_out)
        p.fail("neighbours", "\"walks\" and photons.clustering = \"leave_group_out\" both correct for the photons of "
                             "one walk; set one of them (photons.clustering = \"ignore\" or photons.neighbours = \"photons\")");
    if (s.gather == GatherMode::point_beam || s.gather == GatherMode::photon_beams)
        p.fail("neighbours", std::string("\"walks\" applies to the kNN photon estimates (photons.gather = \"auto\", "
                                         "\"collision\", \"march\", \"threshold\", \"pilot\"), not photons.gather = \"") +
                                 gather_entry(s.gather).name + "\"");
}

// photons.clustering = "leave_group_out" is honoured or refused: it applies to the corrected
// estimator with the constant kernel and ball or linear extinction, and splits k into two halves of
// k / 2 photons (photon/estimate/group_estimate.h), so k is even.
void check_leave_group_out(Params& p, const PhotonMapSettings& s) {
    if (s.clustering != Clustering::leave_group_out) return;
    if (!s.leaves_group_out())
        p.fail("clustering", std::string("\"leave_group_out\" applies to photons.estimator = \"corrected\" with photons.kernel = "
                             "\"constant\" and photons.extinction = \"linear\" or \"ball\" (got estimator \"") +
                                 s.estimator.name() + "\", kernel \"" + s.estimator.kernel().name() + "\", extinction \"" +
                                 (s.extinction == ExtinctionNormalisation::point           ? "point"
                                  : s.extinction == ExtinctionNormalisation::ball          ? "ball"
                                  : s.extinction == ExtinctionNormalisation::linear_signed ? "linear_signed"
                                                                                           : "linear") +
                                 "\"); set photons.clustering = \"ignore\" or change those keys");
    if (s.k % 2)
        p.fail("k", "photons.clustering = \"leave_group_out\" bounds each half of the walk groups by the other half's (k / 2)-th "
                    "photon, so k must be even (got " + std::to_string(s.k) + "; use " + std::to_string(s.k - 1) + " or " +
                    std::to_string(s.k + 1) + ")");
}

// A number in (0, 1] or "auto" (alpha_for).
void read_alpha(Params& p, PhotonMapSettings& s) {
    const char* key = "alpha";
    const char* allowed = "must be a number in (0, 1] or \"auto\" (4/(d+4) per kernel dimension d)";
    const toml::node* n = p.node(key);
    if (!n || n->is_string()) {
        if (n && n->value<std::string>().value_or("") != "auto") p.fail(key, allowed);
        p.choice(key, "auto", {"auto"});
        s.alpha = 0.0;
        return;
    }
    const Range range{0.0, 1.0, true, false};
    if (!n->is_number() || !range.contains(n->value<double>().value_or(-1.0))) p.fail(key, allowed);
    s.alpha = p.real(key, 0.5, range);
}

// photons.estimator, photons.kernel with its parameter (photons.<kernel>_<parameter>, cone_slope; the
// key exists only for that kernel) and photons.k, which the estimator's minimum bounds.
void read_estimator(Params& p, PhotonMapSettings& s) {
    std::vector<std::pair<std::string, Estimator>> estimators;
    for (const Estimator& e : Estimator::all()) estimators.emplace_back(e.name(), e);
    s.estimator = p.choice("estimator", s.estimator, estimators);
    std::vector<std::pair<std::string, Kernel>> kernels;
    for (const Kernel& k : Kernel::all()) kernels.emplace_back(k.name(), k);
    Kernel kernel = p.choice("kernel", s.estimator.kernel(), kernels);
    if (kernel.has_parameter()) {
        const KernelEntry& ke = kernel.entry();
        const std::string key = std::string(ke.name) + "_" + ke.parameter;
        const double v = p.real(key, ke.default_parameter, {ke.parameter_lo, ke.parameter_hi, true, false});
        kernel = Kernel::named(ke.name, v);
    }
    s.estimator = s.estimator.with_kernel(kernel);
    s.k = int(p.integer("k", s.k, Range::closed(1, 1 << 20)));
    if (size_t(s.k) < s.estimator.min_k())
        p.fail("k", std::string("the ") + s.estimator.name() + " estimator needs k >= " +
                        std::to_string(s.estimator.min_k()) +
                        (s.estimator.traits().min_k_reason ? std::string(" (") + s.estimator.traits().min_k_reason + ")" : ""));
    if (const std::string w = s.estimator.warning(size_t(s.k)); !w.empty() && !s.chooses_integrator)
        std::cerr << "warning: " << p.where("k") << ": " << w << "\n";
}

// photons.gather = "photon_beams" takes the estimators that weigh beams, and no forced collisions.
void check_photon_beams(Params& p, const PhotonMapSettings& s) {
    if (s.gather != GatherMode::photon_beams) return;
    if (!s.estimator.traits().photon_beams) {
        std::string allowed;
        for (const Estimator& e : Estimator::all())
            if (e.traits().photon_beams) allowed += (allowed.empty() ? "\"" : ", \"") + std::string(e.name()) + "\"";
        p.fail("estimator", "photons.gather = \"photon_beams\" takes " + allowed + " (the k-th beam weighed or not), not \"" +
                                s.estimator.name() + "\"");
    }
    if (s.forced_collisions)
        p.fail("forced_collisions", "must be false with photons.gather = \"photon_beams\" (its beams are the "
                                    "photons' free flights, which forced collisions replace)");
}

// render.time_limit and what the plan may size under it: what photons.count, render.spp and
// render.passes leave unset.
void read_pass_sizing(Params& render, PhotonMapSettings& s) {
    s.time_limit = render.has("time_limit") ? render.real("time_limit", 0.0, Range::closed(0.0, 1e9)) : 0.0;
    s.passes_given = render.has("passes");
    // Under a limit the plan also sizes the passes of a collision or march gather the user chose (a
    // single candidate: the gather stays the user's); the other gathers are not measured by the pilot.
    if (s.plan_sizes_passes() && s.time_limit > 0.0) {
        // A key the user sets is honoured: photons.count pins the photons per pass, render.spp and
        // render.passes the samples per pass (spp / passes). Unset, the plan sizes them.
        s.size_photons = !s.count_given;
        s.size_samples = !s.passes_given && !render.has("spp");
    }
    if (s.sizes_beam_pass()) {
        s.size_beam_photons = !s.count_given;
        s.size_beam_samples = !s.passes_given && !render.has("spp");
    }
}

}  // namespace

PhotonMapSettings PhotonMapSettings::read(Params& render, Params& p, bool chooses_integrator) {
    PhotonMapSettings s;
    s.chooses_integrator = chooses_integrator;
    s.walk = WalkSettings::read(render);
    s.count = p.integer("count", s.count, Range::closed(1, int64_t(1) << 40));
    s.count_given = p.has("count");
    read_estimator(p, s);
    s.direct = p.choice("direct", s.direct, {{"nee", DirectLighting::nee}, {"photon_map", DirectLighting::photon_map}});
    s.max_radius = p.real("max_radius", s.max_radius, Range::at_least(0.0));
    s.max_bounces = int(p.integer("max_bounces", s.max_bounces, Range::closed(1, 1 << 30)));
    s.memory_budget_fraction = p.real("memory_budget_fraction", s.memory_budget_fraction, {0.0, 1.0, true, false});
    s.final_gather = p.boolean("final_gather", s.final_gather);
    s.forced_collisions = p.boolean("forced_collisions", s.forced_collisions);
    s.extinction = p.choice("extinction", s.extinction,
                            {{"point", ExtinctionNormalisation::point}, {"ball", ExtinctionNormalisation::ball},
                             {"linear", ExtinctionNormalisation::linear},
                             {"linear_signed", ExtinctionNormalisation::linear_signed}});
    s.max_radius_mfp = p.real("max_radius_mfp", s.max_radius_mfp, Range::at_least(0.0));
    s.allocation = p.choice("allocation", s.allocation,
                            {{"importance", PhotonAllocationRule::importance}, {"power", PhotonAllocationRule::power}});
    s.gather = read_gather(p, s.gather);
    s.beam_widths = p.choice("beam_widths", BeamWidths::density,
                             {{"balloon", BeamWidths::balloon}, {"sample_point", BeamWidths::sample_point}, {"density", BeamWidths::density}});
    check_photon_beams(p, s);
    read_pass_sizing(render, s);
    s.gather_queries = int(p.integer("gather_queries", s.gather_queries, Range::closed(1, 1024)));
    s.march_points = p.choice("march_points", s.march_points,
                              {{"fixed", MarchCount::fixed}, {"mass", MarchCount::mass}, {"free_flight", MarchCount::free_flight}});
    s.beam_k = int(p.integer("beam_k", s.beam_k, Range::closed(1, 1 << 20)));
    s.march_max_optical_depth = p.real("march_max_optical_depth", s.march_max_optical_depth, Range::at_least(0.0));
    s.glass_splits = int(p.integer("glass_splits", s.glass_splits, Range::closed(0, 4)));
    s.clustering = p.choice("clustering", s.clustering,
                            {{"leave_group_out", Clustering::leave_group_out}, {"ignore", Clustering::ignore}});
    check_leave_group_out(p, s);
    s.neighbourhood = p.choice("neighbours", s.neighbourhood,
                               {{"photons", Neighbourhood::photons}, {"walks", Neighbourhood::walks}});
    check_walk_neighbours(p, s);
    read_store_probability(p, s);
    s.sampler = p.choice("sampler", s.sampler, sampler_choices());
    if (s.sampler == SamplerKind::sobol && s.count >= (int64_t(1) << 32))
        p.fail("sampler", "\"sobol\" takes at most 2^32 - 1 photons per pass (photons.count = " +
                              std::to_string(s.count) + ")");
    s.schedule = p.choice("schedule", s.schedule,
                          {{"fixed", KSchedule::fixed}, {"progressive", KSchedule::progressive}, {"shrink", KSchedule::shrink}});
    read_alpha(p, s);
    s.k_floor = int(p.integer("k_floor", s.k_floor, Range::closed(1, 1 << 20)));
    if (size_t(s.k_floor) < s.estimator.min_k() + 1)
        p.fail("k_floor", std::string("the ") + s.estimator.name() + " estimator needs k_floor >= " +
                              std::to_string(s.estimator.min_k() + 1) + " (its variance is infinite below)");
    return s;
}

bool PhotonMapSettings::leaves_group_out() const {
    return clustering == Clustering::leave_group_out && estimator.traits().leave_group_out &&
           estimator.kernel().is_constant() && (extinction == ExtinctionNormalisation::ball || extinction == ExtinctionNormalisation::linear);
}

double PhotonMapSettings::alpha_for(int dim) const {
    if (alpha > 0.0) return alpha;
    return schedule == KSchedule::shrink ? 2.0 / 3.0 : optimal_progressive_alpha(dim);
}

int PhotonMapSettings::k_for_pass(int pass_index) const {
    if (schedule == KSchedule::progressive) return radii_for_pass(pass_index, true, false).k;
    if (schedule == KSchedule::fixed) return k;
    const double shrunk = std::round(double(k) * std::pow(double(pass_index) + 1.0, alpha_for(3) - 1.0));
    const int kp = std::max(std::min(k_floor, k), int(shrunk));
    // leave_group_out splits k into two halves of k / 2 (photon/estimate/group_estimate.h).
    return leaves_group_out() && kp % 2 ? kp + 1 : kp;
}

PassEstimators PhotonMapSettings::estimators_for_pass(int pass_index, bool volume, bool surface) const {
    const PassRadii r = radii_for_pass(pass_index, volume, surface);
    return {size_t(r.k), search_radius(), estimator.with_radius_scale(r.volume_scale),
            estimator.with_radius_scale(r.surface_scale), r.beam_scale};
}

PassRadii PhotonMapSettings::radii_for_pass(int pass_index, bool volume, bool surface) const {
    PassRadii r;
    r.k = k;
    if (schedule == KSchedule::shrink) r.k = k_for_pass(pass_index);
    if (schedule != KSchedule::progressive) return r;
    // Photon beams blur in 1D (d = 1, alpha 4/5): the volume's k and scale are the beams' widths'.
    const bool lines = gather == GatherMode::photon_beams;
    const ScheduledKernel points{lines ? 1 : 3, alpha_for(lines ? 1 : 3)}, discs{2, alpha_for(2)};
    std::vector<ScheduledKernel> kernels;
    if (volume) kernels.push_back(points);
    if (surface) kernels.push_back(discs);
    r.k = progressive_k(pass_index, k, k_floor, kernels);
    if (leaves_group_out() && r.k % 2) ++r.k;   // two halves of k / 2 (photon/estimate/group_estimate.h)
    // A map the run does not query keeps scale 1 (its k may not reach its target).
    if (volume) r.volume_scale = progressive_knn_scale(pass_index, k, r.k, points);
    if (surface) r.surface_scale = progressive_knn_scale(pass_index, k, r.k, discs);
    // The beam radiance estimate keeps beam_k: its discs shrink by the radius scale alone. Photon
    // beams: the widths of the pass's k scaled as the volume's.
    r.beam_scale = lines ? r.volume_scale : progressive_radius_scale(pass_index, alpha_for(2), 2);
    return r;
}

}  // namespace vpm
