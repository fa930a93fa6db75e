// libFuzzer target: the OpenVDB density loader on arbitrary file contents.
// A vpm::Error (FileError / ConfigError) is the expected outcome for bad input.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

#include "core/error.h"
#include "io/vdb_io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    static const std::string path =
        (std::filesystem::temp_directory_path() / ("vpm_fuzz_" + std::to_string(getpid()) + ".vdb")).string();
    {
        std::ofstream f(path, std::ios::binary | std::ios::trunc);
        f.write(reinterpret_cast<const char*>(data), std::streamsize(size));
    }
    try {
        (void)vpm::list_vdb_grids(path);
        (void)vpm::load_vdb_density(path, "");
    } catch (const vpm::Error&) {
    }
    return 0;
}
