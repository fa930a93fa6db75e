// Bad input at the process level (issue 6): `vpm render` on each class of bad input exits
// non-zero with exactly one line on stderr naming the file and the key or line, and leaves no
// output behind (an existing output file stays intact). The library-level messages are tested in
// tests/config/config_test.cpp, tests/io/vdb_io_test.cpp and tests/io/mesh_io_test.cpp;
// these tests check what the user sees from the command line.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "core/density_grid.h"
#include "io/vdb_io.h"
#include "support/scratch_dir.h"

namespace fs = std::filesystem;
using namespace vpm;

namespace {


std::string read(const fs::path& p) {
    std::ifstream f(p, std::ios::binary);
    std::stringstream s;
    s << f.rdbuf();
    return s.str();
}

void write(const fs::path& p, const std::string& text) {
    std::ofstream f(p, std::ios::binary);
    f << text;
}

// A valid tiny scene; `extra` is appended (more tables), `render_extra` goes into [render].
std::string scene_text(const std::string& render_extra = "", const std::string& extra = "",
                       const std::string& size = "width = 4\nheight = 4\n") {
    return "[render]\n" + size + "spp = 1\n" + render_extra +
           "\n[camera]\nposition = [0.0, 0.0, 4.0]\nlook_at = [0.0, 0.0, 0.0]\n"
           "\n[[lights]]\ntype = \"point\"\nposition = [0.0, 3.0, 0.0]\nintensity = 5.0\n" +
           extra;
}

std::string grid_medium(const std::string& file, const std::string& grid = "density") {
    return "\n[[media]]\ntype = \"grid\"\nfile = \"" + file + "\"\ngrid = \"" + grid + "\"\n";
}

struct Outcome {
    int code = 0;
    std::string err;
};

Outcome run_vpm(const std::string& args, const fs::path& dir) {
    const fs::path err = dir / "stderr.txt";
    const std::string cmd = std::string(VPM_BINARY) + " " + args +
                            " 2> '" + err.string() + "' > /dev/null";
    const int status = std::system(cmd.c_str());
    Outcome o;
    o.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    o.err = read(err);
    fs::remove(err);
    return o;
}

// Renders `config` (written to DIR/NAME) to DIR/out/render.exr and checks the failure contract.
void expect_clean_failure(const vpm::test::ScratchDir& dir, const std::string& name, const std::string& config,
                          const std::vector<std::string>& needles, const std::string& output = "") {
    const fs::path cfg = dir.path / name;
    write(cfg, config);
    const fs::path out = output.empty() ? dir.path / "out" / "render.exr" : fs::path(output);
    const Outcome o = run_vpm("render -q '" + cfg.string() + "' -o '" + out.string() + "'", dir.path);
    EXPECT_EQ(o.code, 1) << o.err;
    ASSERT_FALSE(o.err.empty());
    EXPECT_EQ(o.err.find('\n'), o.err.size() - 1) << "expected one line on stderr, got:\n" << o.err;
    EXPECT_EQ(o.err.rfind("vpm render: error: ", 0), 0u) << o.err;
    for (const auto& n : needles) EXPECT_NE(o.err.find(n), std::string::npos) << "'" << n << "' not in: " << o.err;
    EXPECT_FALSE(fs::exists(out)) << out;
    EXPECT_FALSE(fs::exists(fs::path(out).replace_extension(".png")));
    EXPECT_FALSE(fs::exists(fs::path(out).replace_extension(".json")));
}

DensityGrid small_grid(float special = 0.5f) {
    std::vector<float> v(4 * 4 * 4, 0.5f);
    v[21] = special;
    return DensityGrid::from_dense(Vec3i(0, 0, 0), Vec3i(4, 4, 4), v);
}

}  // namespace


TEST(BadInput, ValidSceneRendersAndFailureKeepsExistingOutput) {
    const vpm::test::ScratchDir dir;
    write(dir.path / "ok.toml", scene_text());
    const fs::path out = dir.path / "keep.exr";
    const Outcome ok = run_vpm("render -q '" + dir.file("ok.toml") + "' -o '" + out.string() + "'", dir.path);
    ASSERT_EQ(ok.code, 0) << ok.err;
    ASSERT_TRUE(fs::exists(out));
    const std::string before = read(out), before_json = read(fs::path(out).replace_extension(".json"));
    // A failing run aimed at the same output leaves the earlier files byte for byte.
    write(dir.path / "bad.toml", scene_text("widht = 3"));
    const Outcome bad = run_vpm("render -q '" + dir.file("bad.toml") + "' -o '" + out.string() + "'", dir.path);
    EXPECT_EQ(bad.code, 1);
    EXPECT_EQ(read(out), before);
    EXPECT_EQ(read(fs::path(out).replace_extension(".json")), before_json);
    for (const auto& e : fs::directory_iterator(dir.path))
        EXPECT_EQ(e.path().string().find(".tmp-"), std::string::npos) << e.path();
}

TEST(BadInput, MalformedToml) {
    const vpm::test::ScratchDir dir;
    expect_clean_failure(dir, "syntax.toml", "[render\nwidth = 4\n", {"syntax.toml:1"});
}

TEST(BadInput, JsonNumberOutOfRange) {
    // Found by fuzz_config: a JSON config with a number beyond double range escaped as nlohmann's
    // out_of_range (exit 3 "internal error" here, abort in the fuzz target).
    const vpm::test::ScratchDir dir;
    expect_clean_failure(dir, "overflow.json", "{\"render\": {\"width\": 1e99999}}\n", {"overflow.json", "JSON"});
}

// Issue 24: a JSON config that is an array was reported as a TOML syntax error, and a duplicate
// JSON key silently kept the last value.
TEST(BadInput, JsonArrayAndDuplicateKeys) {
    const vpm::test::ScratchDir dir;
    expect_clean_failure(dir, "array.json", "[1, 2]\n", {"array.json", "must be an object", "got a JSON array"});
    expect_clean_failure(dir, "empty_array.json", "[]\n", {"empty_array.json", "got a JSON array"});
    expect_clean_failure(dir, "dup.json", "{\"render\": {\"width\": 4, \"height\": 4, \"width\": 8}}\n",
                         {"dup.json", "duplicate JSON key \"render.width\""});
    expect_clean_failure(dir, "dup_top.json", "{\"render\": {}, \"render\": {}}\n", {"duplicate JSON key \"render\""});
    // Equal keys in different objects are no duplicates.
    write(dir.path / "ok.json", "{\"render\": {\"width\": 4, \"height\": 4, \"spp\": 1}, \"camera\": {\"fov\": 40},"
                                " \"lights\": [{\"type\": \"point\", \"position\": [0, 3, 0], \"intensity\": 1},"
                                " {\"type\": \"point\", \"position\": [0, 2, 0], \"intensity\": 1}]}\n");
    const Outcome o = run_vpm("render -q '" + (dir.path / "ok.json").string() + "' -o '" + (dir.path / "ok.exr").string() + "'", dir.path);
    EXPECT_EQ(o.code, 0) << o.err;
}

TEST(BadInput, UnknownKey) {
    const vpm::test::ScratchDir dir;
    expect_clean_failure(dir, "unknown.toml", scene_text("widht = 3"), {"unknown.toml:", "render.widht"});
}

TEST(BadInput, WrongType) {
    const vpm::test::ScratchDir dir;
    expect_clean_failure(dir, "type.toml", scene_text("seed = \"many\""), {"type.toml:", "render.seed"});
}

TEST(BadInput, OutOfRange) {
    const vpm::test::ScratchDir dir;
    expect_clean_failure(dir, "range.toml",
                         scene_text("", "\n[[media]]\ntype = \"homogeneous\"\ng = 1.5\n"), {"range.toml:", "media.0.g"});
    expect_clean_failure(dir, "range2.toml", scene_text("rr_depth = 0"), {"range2.toml:", "render.rr_depth"});
}

TEST(BadInput, MissingVdb) {
    const vpm::test::ScratchDir dir;
    expect_clean_failure(dir, "missing.toml", scene_text("", grid_medium("nope.vdb")), {"missing.toml:", "media.0.file", "nope.vdb"});
}

TEST(BadInput, UnreadableVdb) {
    const vpm::test::ScratchDir dir;
    fs::create_directories(dir.path / "folder.vdb");   // as root chmod does not stop reads; a folder does
    expect_clean_failure(dir, "unreadable.toml", scene_text("", grid_medium("folder.vdb")),
                         {"unreadable.toml:", "media.0.file", "folder.vdb"});
}

TEST(BadInput, TruncatedAndNotAVdb) {
    const vpm::test::ScratchDir dir;
    const fs::path good = dir.path / "good.vdb";
    vpm::write_vdb_density(good.string(), "density", small_grid());
    const std::string bytes = read(good);
    write(dir.path / "cut.vdb", bytes.substr(0, bytes.size() / 2));
    expect_clean_failure(dir, "cut.toml", scene_text("", grid_medium("cut.vdb")), {"cut.toml:", "media.0.file", "cut.vdb"});
    write(dir.path / "text.vdb", "this is not a VDB file\n");
    expect_clean_failure(dir, "text.toml", scene_text("", grid_medium("text.vdb")), {"text.toml:", "media.0.file", "text.vdb"});
}

TEST(BadInput, AbsentGridName) {
    const vpm::test::ScratchDir dir;
    vpm::write_vdb_density(dir.file("g.vdb"), "smoke", small_grid());
    expect_clean_failure(dir, "absent.toml", scene_text("", grid_medium("g.vdb", "density")),
                         {"absent.toml:", "media.0.grid", "no grid named 'density'", "'smoke' (float)"});
}

TEST(BadInput, WrongGridType) {
    const vpm::test::ScratchDir dir;
    vpm::write_vdb_test_grid(dir.file("vec.vdb"), "velocity", "vec3s");
    vpm::write_vdb_test_grid(dir.file("int.vdb"), "flags", "int32");
    expect_clean_failure(dir, "vec.toml", scene_text("", grid_medium("vec.vdb", "velocity")), {"vec.toml:", "media.0.grid", "vec3s"});
    expect_clean_failure(dir, "int.toml", scene_text("", grid_medium("int.vdb", "flags")), {"int.toml:", "media.0.grid", "int32"});
}

// Documented rule (vdb_io.h): non-finite or negative voxels are rejected, not clamped.
TEST(BadInput, NonFiniteAndNegativeVoxelsRejected) {
    const vpm::test::ScratchDir dir;
    vpm::write_vdb_density(dir.file("nan.vdb"), "density", small_grid(std::numeric_limits<float>::quiet_NaN()));
    vpm::write_vdb_density(dir.file("inf.vdb"), "density", small_grid(std::numeric_limits<float>::infinity()));
    vpm::write_vdb_density(dir.file("neg.vdb"), "density", small_grid(-0.25f));
    expect_clean_failure(dir, "nan.toml", scene_text("", grid_medium("nan.vdb")), {"nan.toml:", "media.0.file", "nan.vdb"});
    expect_clean_failure(dir, "inf.toml", scene_text("", grid_medium("inf.vdb")), {"inf.toml:", "media.0.file", "inf.vdb"});
    expect_clean_failure(dir, "neg.toml", scene_text("", grid_medium("neg.vdb")), {"neg.toml:", "media.0.file", "negative"});
}

TEST(BadInput, EmptyGrid) {
    const vpm::test::ScratchDir dir;
    vpm::write_vdb_test_grid(dir.file("empty.vdb"), "density", "empty_float");
    expect_clean_failure(dir, "empty.toml", scene_text("", grid_medium("empty.vdb")), {"empty.toml:", "media.0.file", "empty.vdb"});
}

TEST(BadInput, MalformedMeshes) {
    const vpm::test::ScratchDir dir;
    write(dir.path / "bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n");
    write(dir.path / "bad.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nend_header\n0\n");
    const std::string mesh = "\n[[shapes]]\ntype = \"mesh\"\nfile = \"";
    expect_clean_failure(dir, "obj.toml", scene_text("", mesh + "bad.obj\"\n"), {"bad.obj:4"});
    expect_clean_failure(dir, "ply.toml", scene_text("", mesh + "bad.ply\"\n"), {"bad.ply"});
}

TEST(BadInput, OutputFolderNotWritable) {
    const vpm::test::ScratchDir dir;
    write(dir.path / "plain_file", "x");   // as root chmod does not help: a path under a regular file
    const std::string out = (dir.path / "plain_file" / "sub" / "render.exr").string();
    expect_clean_failure(dir, "ok.toml", scene_text(), {"plain_file"}, out);
}

TEST(BadInput, ImageTooBigForMemory) {
    const vpm::test::ScratchDir dir;
    expect_clean_failure(dir, "huge.toml", scene_text("", "", "width = 65536\nheight = 65536\n"),
                         {"huge.toml:", "render.width", "GB"});
}

// Found by fuzz/fuzz_vdb (libFuzzer + ASan, 2026-11-22): a box.vdb with bytes changed inside a
// blosc-compressed leaf buffer. OpenVDB 10's io::bloscFromStream allocates the compressed size
// it reads from the file unchecked (here ~1e14 bytes); ASan aborts on that, a normal build gets
// std::bad_alloc or (with overcommit) a decompression error, which vdb_io.cpp turns into a
// FileError: one line, exit 1, nothing written.
TEST(FuzzRegression, VdbWithGarbageBloscSize) {
#if defined(__SANITIZE_ADDRESS__) || (defined(__has_feature) && __has_feature(address_sanitizer))
    // ASan's throwing operator new reports out-of-memory instead of throwing std::bad_alloc, so
    // under ASan this input aborts inside OpenVDB whatever vpm does.
    GTEST_SKIP() << "aborts under ASan inside OpenVDB (unchecked blosc size); checked in normal builds";
#endif
    const vpm::test::ScratchDir dir;
    fs::copy_file(fs::path(VPM_TEST_DATA_DIR) / "fuzz" / "vdb_blosc_garbage_size.vdb", dir.path / "garbage.vdb");
    expect_clean_failure(dir, "garbage.toml", scene_text("", grid_medium("garbage.vdb")),
                         {"garbage.toml:", "media.0.file", "garbage.vdb"});
}
