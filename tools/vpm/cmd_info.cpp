// vpm info CONFIG | FILE.vdb [--set KEY=VALUE]... [--json]
// What a scene or a VDB holds before rendering it (lib/analysis/scene_info.h).
#include <cctype>
#include <cstdio>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "analysis/scene_info.h"
#include "arguments.h"
#include "command.h"
#include "render/run/run_config.h"

namespace {

bool is_vdb(const std::string& path) {
    return path.size() >= 4 && path.compare(path.size() - 4, 4, ".vdb") == 0;
}

// Case-insensitive: "IMG.EXR" is an image as well.
bool has_extension(const std::string& path, const std::string& ext) {
    if (path.size() < ext.size()) return false;
    for (size_t i = 0; i < ext.size(); ++i)
        if (std::tolower(static_cast<unsigned char>(path[path.size() - ext.size() + i])) != ext[i]) return false;
    return true;
}

int run_info(int argc, char** argv) {
    CLI::App app("What a scene config or a VDB file holds, before rendering it. A config: world bounds; per medium "
                 "its bounds, voxel size, density range and active voxels, sigma_t, albedo, g and the optical thickness "
                 "across its centre; the lights and their power; the shapes; the camera and the fraction of its pixels "
                 "that meet a medium or a surface. A VDB: every grid's index box, voxel size, world bounds, active "
                 "voxels, density range and optical thickness at sigma_t_scale = 1, and a camera that frames them.",
                 "vpm info");
    std::string target;
    std::vector<std::string> sets;
    bool json = false;
    app.add_option("target", target, "Scene config (TOML, or a run's JSON sidecar) or an OpenVDB file (.vdb)")
        ->required()
        ->check(CLI::ExistingFile);
    app.add_option("--set", sets, "Override a config key by dotted path, as vpm render --set (repeatable; configs only)")
        ->allow_extra_args(false);
    app.add_flag("--json", json, "One JSON object instead of text");
    if (!vpm::cli::parse_arguments(app, argc, argv)) return 0;
    nlohmann::json info;
    if (has_extension(target, ".exr"))
        throw vpm::cli::UsageError("target: " + target + " is an OpenEXR image; vpm info reads a scene config (TOML, or a "
                                   "run's JSON sidecar such as the .json beside the image) or an OpenVDB file (.vdb)");
    if (is_vdb(target)) {
        if (!sets.empty()) throw vpm::cli::UsageError("--set: applies to a scene config, not to a VDB file");
        info = vpm::vdb_info(target);
    } else {
        info = vpm::scene_info(vpm::RunConfig::load(target, sets));
    }
    if (json) std::printf("%s\n", info.dump(2).c_str());
    else std::fputs(vpm::info_text(info).c_str(), stdout);
    return 0;
}

}  // namespace

VPM_REGISTER_COMMAND({"info", "what a scene config or a VDB file holds: bounds, densities, lights, what the camera sees", run_info});
