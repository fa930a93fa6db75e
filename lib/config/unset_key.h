#pragma once
// `vpm render --unset KEY`: removes a key the config file (or a base config) sets, so that its
// default, or the automatic choice the key would pin, applies again (e.g. --unset photons.count
// under render.time_limit lets the plan size the photons per pass). KEY is a dotted path as for
// --set ("render.spp", "media.0.g"); tables and array entries cannot be removed, only values.
#include <string>

#include "config/params.h"

namespace vpm {

// Throws ConfigError "--unset KEY: ..." when the document does not set KEY to a value, naming
// the file.
void unset_key(ConfigDocument& doc, const std::string& key);

}  // namespace vpm
