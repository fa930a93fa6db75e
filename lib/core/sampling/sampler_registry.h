#pragma once
// The samplers users choose by name (render.sampler, photons.sampler): core/sampling/sampler.h.
#include <string>
#include <utility>
#include <vector>

#include "core/sampling/sampler.h"

namespace vpm {

struct SamplerEntry {
    const char* name;
    SamplerKind kind;
    const char* summary;   // one line for --help and the docs
};

const std::vector<SamplerEntry>& sampler_entries();
std::vector<std::string> sampler_names();
// (name, kind) pairs for Params::choice.
std::vector<std::pair<std::string, SamplerKind>> sampler_choices();
const char* sampler_name(SamplerKind kind);

}  // namespace vpm
