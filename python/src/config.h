#pragma once
// A loaded config as Python sees it (vpm.Config): the library's RunConfig, shared so that renders
// and photon maps made from it keep it alive, and how long loading took (the sidecar's "load" phase).
#include <memory>

#include "render/run/run_config.h"

namespace vpm::python {

struct Config {
    std::shared_ptr<const RunConfig> run;
    double load_seconds = 0.0;
};

}  // namespace vpm::python
