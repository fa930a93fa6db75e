// libFuzzer target: the OBJ and PLY loaders on arbitrary file contents. The first byte picks
// the format (even: OBJ, odd: PLY); a vpm::FileError is the expected outcome for bad input.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

#include "core/error.h"
#include "io/mesh_io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size == 0) return 0;
    const bool ply = data[0] & 1;
    const std::string path = (std::filesystem::temp_directory_path() /
                              ("vpm_fuzz_" + std::to_string(getpid()) + (ply ? ".ply" : ".obj")))
                                 .string();
    {
        std::ofstream f(path, std::ios::binary | std::ios::trunc);
        f.write(reinterpret_cast<const char*>(data + 1), std::streamsize(size - 1));
    }
    try {
        (void)vpm::load_mesh(path);
    } catch (const vpm::Error&) {
    }
    return 0;
}
