#pragma once
// Integrators by name: render.integrator picks one. Every entry's settings are read from each
// config (so every key is validated and the resolved config is complete whichever integrator
// runs); only the chosen one is built.
//
//   name          file                       reads
//   "path"        path_tracer.h              [render] max_depth, rr_depth
//   "photon_map"  photon_map_integrator.h    [photons], [render] max_depth, rr_depth
//   "auto"        photon_map_integrator.h    the same: the photon map whose plan may choose the path tracer
//
// Adding an integrator: one file pair with its Integrator, its IntegratorSettings and a reader,
// and one line in the table in integrator_registry.cpp (with the reader's declaration beside it);
// docs/config.md's [render] row names it (tests/tools/registry_docs_test.cpp fails until it does). An
// integrator must leave the scene's image unbiased or document its bias (the photon map's is
// the estimator's, measured in docs/), give the same image for a seed on any thread count, and
// report what it built and measured in its typed RunStats.
#include <memory>
#include <string>
#include <vector>

#include "render/integrator.h"
#include "config/params.h"

namespace vpm {

struct IntegratorType {
    const char* name;
    const char* summary;
    // Reads the integrator's keys: `render` is the [render] table, `root` the whole config
    // (for tables of its own, which it finishes itself).
    std::unique_ptr<IntegratorSettings> (*read)(Params& render, Params& root);
};

const std::vector<IntegratorType>& integrator_types();
std::vector<std::string> integrator_names();

}  // namespace vpm
