#include "data_files.h"

#include <cstdlib>
#include <system_error>

namespace vpm::cli {

std::filesystem::path data_file(const std::string& relative) {
    namespace fs = std::filesystem;
    if (const char* dir = std::getenv("VPM_DATA_DIR"); dir && *dir) return fs::path(dir) / relative;
    std::error_code ec;
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    if (!ec) {
        const fs::path installed = exe.parent_path().parent_path() / "share" / "vpm" / relative;
        if (fs::exists(installed, ec)) return installed;
    }
    return fs::path(VPM_SOURCE_DIR) / relative;
}

}  // namespace vpm::cli
