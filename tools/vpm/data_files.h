#pragma once
// Where the vpm tool finds the files it ships beside the binary (plot scripts, stress scenes):
// $VPM_DATA_DIR if set, else <prefix>/share/vpm for an installed binary (bin/vpm), else the
// source tree it was built from. The library never looks for files itself; tools pass paths in.
#include <filesystem>
#include <string>

namespace vpm::cli {

std::filesystem::path data_file(const std::string& relative);

}  // namespace vpm::cli
