// Issue 12, memory: `vpm render` with a photon count that cannot fit stops at once with a clear
// error (projected from the 65536-photon pilot chunk of the photon pass), exit code 1, no output;
// before, photons.count = 1e12 ended in "internal error: std::bad_alloc" (exit 3) and 3e9 grew
// past 5 GB with no progress line. The guard itself is checked directly as well.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/error.h"
#include "photon/trace/photon_budget.h"

namespace fs = std::filesystem;
using namespace vpm;

TEST(PhotonMemory, CountThatCannotFitFailsFastWithAClearError) {
    const fs::path dir = fs::temp_directory_path() / ("vpm_photon_memory_cli_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    const fs::path out = dir / "img.exr", err_file = dir / "stderr.txt";
    const std::string cmd = std::string(VPM_BINARY) + " render " + VPM_SOURCE_DIR +
                            "/configs/homogeneous.toml --set render.integrator=photon_map --set photons.count=1000000000000"
                            " --set render.width=8 --set render.height=8 --threads 1 -o " +
                            out.string() + " 2> " + err_file.string() + " > /dev/null";
    const int status = std::system(cmd.c_str());
    std::ifstream in(err_file);
    std::stringstream s;
    s << in.rdbuf();
    const std::string err = s.str();
    EXPECT_EQ(WEXITSTATUS(status), 1) << err;
    EXPECT_NE(err.find("cannot fit in memory"), std::string::npos) << err;
    EXPECT_NE(err.find("photons.count"), std::string::npos) << err;
    EXPECT_EQ(err.find("bad_alloc"), std::string::npos) << err;
    EXPECT_FALSE(fs::exists(out));
    fs::remove_all(dir);
}

TEST(PhotonMemory, GuardProjectsFromThePilotAndLogsProgress) {
    std::ostringstream log;
    const auto guard = make_photon_pass_guard(1e9, &log, 0.0);
    PhotonTraceProgress p;
    p.total = 1000000;
    p.emitted = 65536;
    p.stored = 65536;   // one stored per emitted: 1e6 stored, ~1.3e8 bytes: fits in 1 GB
    p.seconds = 1.0;
    EXPECT_NO_THROW(guard(p));
    EXPECT_NE(log.str().find("trace: "), std::string::npos) << log.str();
    EXPECT_NEAR(projected_stored_photons(p), 1e6, 1e-6);
    p.total = 100000000;   // 1e8 stored: ~1.3e10 bytes
    try {
        guard(p);
        FAIL() << "no error";
    } catch (const Error& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("cannot fit in memory"), std::string::npos) << m;
        EXPECT_NE(m.find("fits"), std::string::npos) << m;
    }
}

// Issue 61: photon beams are projected like photons (before, the guard counted stored photons
// only, and the photon-beams gather stores none: photons.count = 1e7 in the furnace ran 81 s into
// std::bad_alloc at 1,172 bytes per beam).
TEST(PhotonMemory, BeamsAreProjectedWithTheirBvh) {
    const auto guard = make_photon_pass_guard(1e9, nullptr);
    PhotonTraceProgress p;
    p.total = 10000000;
    p.emitted = 65536;
    p.beams = 4 * 65536;   // 4 beams per photon: 4e7 beams
    EXPECT_NEAR(projected_beams(p), 4e7, 1e-3);
    EXPECT_GT(peak_bytes_per_beam(), 1000.0);   // the record, the width and up to 9 BVH pieces
    try {
        guard(p);
        FAIL() << "no error";
    } catch (const Error& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("cannot fit in memory"), std::string::npos) << m;
        EXPECT_NE(m.find("photon beams"), std::string::npos) << m;
        // The count that fits: 1e9 bytes over 4 beams per photon.
        const double fits = std::floor(1e9 / (4.0 * peak_bytes_per_beam()));
        std::ostringstream want;
        want.precision(3);
        want << "photons.count <= " << fits << " fits";
        EXPECT_NE(m.find(want.str()), std::string::npos) << m;
    }
    p.total = 100000;   // 4e5 beams: fits
    EXPECT_NO_THROW(guard(p));
}

TEST(PhotonMemory, PhotonBeamsCountThatCannotFitFailsFast) {
    const fs::path dir = fs::temp_directory_path() / ("vpm_photon_beams_memory_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    const fs::path out = dir / "img.exr", err_file = dir / "stderr.txt";
    const std::string cmd = "timeout 120 " + std::string(VPM_BINARY) + " render " + VPM_SOURCE_DIR +
                            "/configs/homogeneous.toml --set render.integrator=photon_map --set photons.gather=photon_beams"
                            " --set photons.count=1000000000000 --set render.width=8 --set render.height=8 --threads 1 -o " +
                            out.string() + " 2> " + err_file.string() + " > /dev/null";
    const int status = std::system(cmd.c_str());
    std::ifstream in(err_file);
    std::stringstream s;
    s << in.rdbuf();
    const std::string err = s.str();
    EXPECT_EQ(WEXITSTATUS(status), 1) << err;
    EXPECT_NE(err.find("cannot fit in memory"), std::string::npos) << err;
    EXPECT_NE(err.find("photon beams"), std::string::npos) << err;
    EXPECT_FALSE(fs::exists(out));
    fs::remove_all(dir);
}
