#pragma once
// render/: how a scene is measured. An integrator estimates the radiance arriving along camera
// rays; it owns its settings (typed values read from the config), the passes it needs before the
// camera pass (the photon pass of the photon map), and the statistics it reports.
//
//   integrator.h           the interfaces below
//   integrator_registry.h  integrators by name ("path", "photon_map"): one line each
//   run_config.h           a config file read into Scene + RenderSettings + integrator settings
//   run.h                  one run: passes, camera pass, typed RunStats, the JSON record
//   run_stats.h            the typed statistics, with a section per integrator or gather
//
// Estimates must be independent across calls given independent Rng streams; the render loop
// averages them.
#include <memory>
#include <ostream>
#include <string>

#include "core/math.h"
#include "core/sampling/rng.h"

namespace vpm {

class Scene;
struct RunStats;

// What a run hands to an integrator's passes.
struct PassContext {
    uint64_t seed = 1;
    uint64_t stream_offset = 0;    // independent repeats and passes with the same seed
    uint64_t run_stream_offset = 0;   // the run's own offset (the same for all its passes)
    int pass = 0;                  // the pass's index, counting from render.first_pass
    int configured_spp = 16;       // render.spp / render.passes: the pass's samples unless sized
    bool first_of_run = true;      // this run's first pass (logs say what was built once)
    bool progress = true;          // progress bars on stderr
    std::ostream* log = nullptr;   // one line per phase; null: silent
};

class Integrator {
public:
    virtual ~Integrator() = default;
    // Runs the passes the camera pass needs (e.g. the photon pass), recording their phases and
    // statistics in `stats`. The default has none.
    virtual void prepare(const PassContext& context, RunStats& stats) {}
    // Radiance travelling towards the camera along -ray.dir.
    virtual Rgb radiance(const Ray& ray, Rng& rng) const = 0;
    // Adds what the camera pass counted (estimator cases, ...) to `stats`.
    virtual void collect(RunStats& stats, std::ostream* log) const {}
    virtual std::string name() const = 0;
    // True when prepare() does nothing per pass: the run may then render several passes in one
    // sweep over the image (render_passes), which gives exactly the image of rendering them apart.
    virtual bool stateless_passes() const { return false; }
    // Camera samples per pixel for the pass prepare() has just set up: `configured` unless the
    // integrator sized its passes itself (the photon map's plan under render.time_limit).
    virtual int samples_per_pass(int configured) const { return configured; }
    // Seconds of the run's first prepare() that later passes do not repeat (the photon map's pilot):
    // a time limit reckons the passes that still fit without them.
    virtual double one_off_seconds() const { return 0.0; }
};

// An integrator's typed settings, read from the config by its registry entry; builds the
// integrator for a scene.
class IntegratorSettings {
public:
    virtual ~IntegratorSettings() = default;
    virtual std::unique_ptr<Integrator> create(const Scene& scene) const = 0;
};

}  // namespace vpm
