#pragma once
// The stress matrix: stiff and extreme cases run one axis at a time around small base
// scenes (configs/stress/), plus special cells. Every cell records what a user needs to trust a
// run: non-finite pixels and samples (must be 0), the photon pass's energy balance (emitted =
// absorbed + escaped + truncated, to 1e-6 relative), photon paths cut by the path-length cap,
// wall time, and the relative error against a reference where one is affordable (the white
// furnace's analytic 0.5, the unbiased path tracer on the same scene, or the untranslated scene).
//
// `vpm stress` runs it and writes STRESS.md; tests/stress runs the quick subset and asserts the
// NaN/Inf and energy columns for every cell.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <ostream>
#include <string>
#include <vector>

namespace vpm {

struct StressOptions {
    bool quick = false;                       // CI-sized subset: tiny images and photon counts, no path-traced references
    std::filesystem::path configs;            // folder with furnace.toml, sphere.toml, dense_voxel.toml
    std::filesystem::path out;                // scratch folder (the dense-voxel VDB is written here)
    std::ostream* log = nullptr;              // one line per cell as it finishes
    std::function<bool(const std::string&)> filter;   // run only cells whose "group/label" passes (null: all)
};

struct StressCell {
    std::string group, label, scene;   // axis or special case, value, base scene file
    uint64_t nonfinite_pixels = 0;     // NaN/Inf in the final image
    uint64_t nonfinite_samples = 0;    // non-finite estimates the render loop counted and left out
    bool photon_pass = false;
    double energy_imbalance = 0.0;     // |emitted - absorbed - escaped - truncated| / emitted, worst channel
    uint64_t emitted = 0, stored = 0, truncated_paths = 0;
    double truncated_energy = 0.0;     // fraction of the emitted power cut by the cap
    double seconds = 0.0;
    double value = 0.0;                // image mean (all pixels and channels)
    bool has_reference = false;
    std::string reference_kind;        // "analytic 0.5", "path tracer", "untranslated"
    double reference = 0.0;
    double rel_error = 0.0;            // (value - reference) / reference, or mean |pixel diff| / mean for "untranslated"
    std::string note;
    bool ok() const { return nonfinite_pixels == 0 && nonfinite_samples == 0 && energy_imbalance <= 1e-6; }
};

struct StressReport {
    std::vector<StressCell> cells;
    bool quick = false;
    double seconds = 0.0;
    bool all_ok() const;
    std::string to_markdown(const std::string& command, const std::string& machine) const;
};

StressReport run_stress(const StressOptions& options);

// The "group/label" keys of the cells run_stress would run (quick: the CI subset), before the filter.
std::vector<std::string> stress_cell_keys(bool quick);

}  // namespace vpm
