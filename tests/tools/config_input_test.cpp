// Config input at the process level (issue 13): nesting and size bounded before the TOML parser
// sees a file, folders named as folders, --set errors that blame the --set.
#include <gtest/gtest.h>

#include "support/vpm_process.h"

using namespace vpm::test;

namespace {

void expect_error(const ScratchDir& dir, const std::string& args, const std::vector<std::string>& needles) {
    const Outcome o = run_vpm("render -q " + args + " -o " + quote(dir.path / "out" / "r.exr"), dir.path);
    EXPECT_EQ(o.code, 1) << args << "\n" << o.err;
    EXPECT_TRUE(o.one_line()) << args << "\n" << o.err;
    EXPECT_EQ(o.err.rfind("vpm render: error: ", 0), 0u) << o.err;
    for (const auto& n : needles) EXPECT_NE(o.err.find(n), std::string::npos) << "'" << n << "' not in: " << o.err;
    EXPECT_FALSE(fs::exists(dir.path / "out" / "r.exr"));
}

std::string repeat(const std::string& s, int n, const std::string& sep = "") {
    std::string out;
    for (int i = 0; i < n; ++i) out += (i ? sep : "") + s;
    return out;
}

}  // namespace

TEST(ConfigInput, DeepNestingIsRefusedBeforeParsing) {
    // A 40,000-level dotted header crashed toml++ (SIGSEGV); every form of nesting is bounded.
    ScratchDir dir;
    write_file(dir.path / "header.toml", "[" + repeat("a", 40000, ".") + "]\n");
    expect_error(dir, quote(dir.path / "header.toml"), {"header.toml:1:", "nesting deeper than 64"});
    write_file(dir.path / "aot.toml", tiny_scene() + "\n[[" + repeat("b", 5000, ".") + "]]\n");
    expect_error(dir, quote(dir.path / "aot.toml"), {"aot.toml:15:", "nesting"});
    write_file(dir.path / "key.toml", repeat("k", 20000, ".") + " = 1\n");
    expect_error(dir, quote(dir.path / "key.toml"), {"key.toml:1:", "nesting"});
    write_file(dir.path / "array.toml", "x = " + repeat("[", 20000) + repeat("]", 20000) + "\n");
    expect_error(dir, quote(dir.path / "array.toml"), {"array.toml:1:", "nesting"});
    write_file(dir.path / "inline.toml", "x = " + repeat("{ y = ", 20000) + "1" + repeat(" }", 20000) + "\n");
    expect_error(dir, quote(dir.path / "inline.toml"), {"inline.toml:1:", "nesting"});
    // Through a base config, a --set key and a --set value.
    write_file(dir.path / "inc.toml", "base = \"header.toml\"\n");
    expect_error(dir, quote(dir.path / "inc.toml"), {"header.toml:1:", "nesting"});
    write_file(dir.path / "s.toml", tiny_scene());
    expect_error(dir, quote(dir.path / "s.toml") + " --set " + repeat("a", 1000, ".") + "=1", {"--set a.a", "limit is 64"});
    expect_error(dir, quote(dir.path / "s.toml") + " --set 'render.spp=" + repeat("[", 5000) + "'", {"--set render.spp", "nesting"});
    // Dots inside strings, comments and numbers are not nesting.
    write_file(dir.path / "dots.toml", tiny_scene("# " + repeat(".", 500) + "\n") + "\n[[media]]\ntype = \"homogeneous\"\n"
                                       "sigma_t_scale = 1.000000\n");
    const Outcome ok = run_vpm("render -q " + quote(dir.path / "dots.toml") + " -o " + quote(dir.path / "dots.exr"), dir.path);
    EXPECT_EQ(ok.code, 0) << ok.err;
}

TEST(ConfigInput, OversizedConfigIsRefused) {
    ScratchDir dir;
    write_file(dir.path / "big.toml", tiny_scene() + "# " + std::string(2 << 20, 'x') + "\n");
    expect_error(dir, quote(dir.path / "big.toml"), {"big.toml", "the limit is 1048576"});
}

TEST(ConfigInput, FolderGivenAsConfigBaseOrMeshIsNamedAsSuch) {
    ScratchDir dir;
    fs::create_directories(dir.path / "folder");
    expect_error(dir, quote(dir.path / "folder"), {"folder: cannot read config file: it is a folder"});
    write_file(dir.path / "inc.toml", "base = \"folder\"\n");
    expect_error(dir, quote(dir.path / "inc.toml"), {"inc.toml:1: base:", "it is a folder"});
    write_file(dir.path / "mesh.toml",
               tiny_scene("", "\n[[shapes]]\ntype = \"mesh\"\nfile = \"folder\"\nmaterial = \"black\"\n"));
    expect_error(dir, quote(dir.path / "mesh.toml"), {"mesh.toml:", "shapes.0.file", "is a folder"});
}

TEST(ConfigInput, SetErrorsBlameTheSet) {
    ScratchDir dir;
    write_file(dir.path / "base.toml", tiny_scene());
    write_file(dir.path / "inc.toml", "base = \"base.toml\"\n[render]\nspp = 2\n");
    // -o becomes render.output: a --set that replaces [render] must be the one blamed.
    expect_error(dir, quote(dir.path / "inc.toml") + " --set render=3", {"--set render", "expected a table"});
    expect_error(dir, quote(dir.path / "inc.toml") + " --set media.-1.g=0", {"--set media.-1.g=0", "'media' has no entries"});
    expect_error(dir, quote(dir.path / "inc.toml") + " --set lights.-1.intensity=0",
                 {"'-1' is not an index of 'lights', which has 1 entries (0 to 0)"});
    expect_error(dir, quote(dir.path / "inc.toml") + " --set lights.3.intensity=0", {"index 3 is past the end of 'lights'"});
    expect_error(dir, quote(dir.path / "inc.toml") + " --set render.spp.x=1", {"'render.spp' is a single value"});
}

// Issue 61: the messages of undesigned --set values, seeds and files.
TEST(ConfigInput, SetValuesNameTheSetAndWhatIsAllowed) {
    ScratchDir dir;
    write_file(dir.path / "s.toml", tiny_scene());
    const std::string s = quote(dir.path / "s.toml");
    // Seeds past 2^63 - 1: an integer out of range (was "expected an integer, got a string").
    expect_error(dir, s + " --set render.seed=9223372036854775808", {"--set render.seed", "integer out of range", "9223372036854775807"});
    // A newline inside a value: the rest was ignored silently.
    expect_error(dir, s + " --set 'render.width=16\nrender.height=4'", {"--set render.width", "more than one value"});
    // A whole table replaced [render], dropping the file's keys silently.
    expect_error(dir, s + " --set 'render={width=16}'", {"--set render={width=16}", "is a table", "--set render.KEY=VALUE"});
    // Values set on the command line are blamed on the --set, not on a line of the file.
    expect_error(dir, s + " --set 'camera.position=[1e308,0,0]'", {"--set camera.position", "too far from camera.look_at"});
    expect_error(dir, s + " --set lights.0=5", {"--set lights.0: lights.0: expected a table", "got an integer"});
    expect_error(dir, s + " --set 'shapes=[{type=\"sphere\", center=[0,0,0], radius=-1}]'", {"--set shapes: shapes.0.radius"});
    // A table created by --set is still merged with later --set keys.
    const Outcome ok = run_vpm("render -q " + s + " --set render.seed=9223372036854775807 -o " + quote(dir.path / "ok.exr"), dir.path);
    EXPECT_EQ(ok.code, 0) << ok.err;
}

TEST(ConfigInput, JsonSeedsPast2To63AreRefusedNotWrapped) {
    ScratchDir dir;
    write_file(dir.path / "s.json", "{\"render\": {\"width\": 4, \"height\": 4, \"spp\": 1, \"seed\": 9223372036854775808},"
                                    " \"lights\": [{\"type\": \"point\", \"position\": [0, 3, 0], \"intensity\": 5}]}");
    expect_error(dir, quote(dir.path / "s.json"), {"s.json: render.seed: integer 9223372036854775808 is out of range", "2^63 - 1"});
}

TEST(ConfigInput, AnImageGivenAsAConfigIsNamedAsSuch) {
    ScratchDir dir;
    write_file(dir.path / "s.toml", tiny_scene());
    const Outcome r = run_vpm("render -q " + quote(dir.path / "s.toml") + " -o " + quote(dir.path / "img.exr"), dir.path);
    ASSERT_EQ(r.code, 0) << r.err;
    expect_error(dir, quote(dir.path / "img.exr"), {"img.exr: cannot read config file: it is an OpenEXR image"});
    const Outcome info = run_vpm("info " + quote(dir.path / "img.exr"), dir.path);
    EXPECT_EQ(info.code, 2) << info.err;
    EXPECT_TRUE(info.one_line()) << info.err;
    EXPECT_NE(info.err.find("is an OpenEXR image; vpm info reads a scene config"), std::string::npos) << info.err;
    EXPECT_EQ(info.err.find("TOML syntax error"), std::string::npos) << info.err;
}

TEST(ConfigInput, ProgressLinesWhenStderrIsNotATerminal) {
    // The interval is 5 s by default; VPM_PROGRESS_SECONDS=0 makes every step print, so the test
    // does not depend on how long the render takes.
    ScratchDir dir;
    write_file(dir.path / "s.toml", tiny_medium_scene());
    const Outcome o = run_vpm(quote(dir.path / "s.toml").insert(0, "render ") + " -o " + quote(dir.path / "p.exr"), dir.path,
                              "VPM_PROGRESS_SECONDS=0 ");
    ASSERT_EQ(o.code, 0) << o.err;
    EXPECT_NE(o.err.find("\nrender: "), std::string::npos) << o.err;
    EXPECT_NE(o.err.find("% ("), std::string::npos) << o.err;
    EXPECT_NE(o.err.find("render: 100% (4/4)"), std::string::npos) << o.err;
    EXPECT_EQ(o.err.find('\r'), std::string::npos) << "terminal codes in a log";
    // -q keeps it silent.
    const Outcome q = run_vpm("render -q " + quote(dir.path / "s.toml") + " -o " + quote(dir.path / "q.exr"), dir.path,
                              "VPM_PROGRESS_SECONDS=0 ");
    EXPECT_EQ(q.err, "");
}
