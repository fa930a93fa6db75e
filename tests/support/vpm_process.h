#pragma once
// Running the built `vpm` binary from a test (VPM_BINARY) and looking at what a user sees: the
// exit code, stderr and stdout, and the files left in a private temporary folder.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "scratch_dir.h"

namespace vpm::test {

namespace fs = std::filesystem;

inline std::string read_file(const fs::path& p) {
    std::ifstream f(p, std::ios::binary);
    std::stringstream s;
    s << f.rdbuf();
    return s.str();
}

inline void write_file(const fs::path& p, const std::string& text) {
    std::ofstream f(p, std::ios::binary);
    f << text;
}

inline std::string quote(const fs::path& p) { return "'" + p.string() + "'"; }

struct Outcome {
    int code = -1;   // exit code; -1 when killed by a signal
    std::string out, err;
    // Exactly one line on stderr.
    bool one_line() const { return !err.empty() && err.find('\n') == err.size() - 1; }
};

// Runs `vpm ARGS` (a shell fragment: quote paths with quote()) with `env` (e.g.
// "VPM_PROGRESS_SECONDS=0 ") in front, capturing stdout and stderr through files in `dir`.
inline Outcome run_vpm(const std::string& args, const fs::path& dir, const std::string& env = "") {
    const fs::path out = dir / ".stdout.txt", err = dir / ".stderr.txt";
    const std::string cmd = env + "'" + std::string(VPM_BINARY) + "' " + args + " > " + quote(out) + " 2> " + quote(err);
    const int status = std::system(cmd.c_str());
    Outcome o;
    o.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    o.out = read_file(out);
    o.err = read_file(err);
    fs::remove(out);
    fs::remove(err);
    return o;
}

// A valid tiny scene (4x4, 1 spp, a point light, no media): renders in milliseconds.
inline std::string tiny_scene(const std::string& render_extra = "", const std::string& extra = "",
                              double intensity = 5.0) {
    std::ostringstream s;
    s << "[render]\nwidth = 4\nheight = 4\nspp = 1\n" << render_extra
      << "\n[camera]\nposition = [0.0, 0.0, 4.0]\nlook_at = [0.0, 0.0, 0.0]\n"
         "\n[[lights]]\ntype = \"point\"\nposition = [0.0, 3.0, 0.0]\nintensity = "
      << intensity << "\n" << extra;
    return s.str();
}

// A tiny scene with a homogeneous medium, so the image is not black.
inline std::string tiny_medium_scene(double intensity = 5.0, const std::string& render_extra = "") {
    return tiny_scene(render_extra,
                      "\n[[media]]\ntype = \"homogeneous\"\nshape = \"sphere\"\ncenter = [0.0, 0.0, 0.0]\n"
                      "radius = 1.0\nsigma_t_scale = 1.0\nalbedo = 0.8\n",
                      intensity);
}

// Files in `dir` whose name contains ".tmp-" (temporaries of atomic writes).
inline int temporaries_in(const fs::path& dir) {
    int n = 0;
    for (const auto& e : fs::recursive_directory_iterator(dir))
        n += e.path().filename().string().find(".tmp-") != std::string::npos;
    return n;
}

}  // namespace vpm::test
