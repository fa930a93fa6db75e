#include "core/sampling/sampler_registry.h"

#include "core/registry.h"

namespace vpm {

const std::vector<SamplerEntry>& sampler_entries() {
    static const std::vector<SamplerEntry> entries = {
        {"independent", SamplerKind::independent, "independent PCG32 streams (per pixel and pass, per photon batch)"},
        {"stratified", SamplerKind::stratified,
         "jittered grids over consecutive dimension pairs, per pixel and pass / per photon batch"},
        {"sobol", SamplerKind::sobol,
         "Owen-scrambled Sobol' points (Joe & Kuo), per pixel and pass / over a pass's photons"},
    };
    return entries;
}

std::vector<std::string> sampler_names() { return registry_names(sampler_entries()); }

std::vector<std::pair<std::string, SamplerKind>> sampler_choices() {
    std::vector<std::pair<std::string, SamplerKind>> choices;
    for (const SamplerEntry& e : sampler_entries()) choices.emplace_back(e.name, e.kind);
    return choices;
}

const char* sampler_name(SamplerKind kind) {
    for (const SamplerEntry& e : sampler_entries())
        if (e.kind == kind) return e.name;
    return "?";
}

}  // namespace vpm
