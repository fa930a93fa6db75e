// Output files at the process level (issue 13): what `vpm render -o` may replace, when it checks,
// what it leaves after a signal, and that concurrent runs leave one run's files.
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <cmath>
#include <limits>

#include <nlohmann/json.hpp>

#include "render/image_io.h"
#include "render/staged_file.h"
#include "../support/vpm_process.h"

using namespace vpm;
using namespace vpm::test;

namespace {

// One failed render: exit 1, one error line naming `needle`, nothing written beside `out`.
void expect_refused(const ScratchDir& dir, const std::string& args, const std::string& needle) {
    const Outcome o = run_vpm("render -q " + args, dir.path);
    EXPECT_EQ(o.code, 1) << o.err;
    EXPECT_TRUE(o.one_line()) << o.err;
    EXPECT_EQ(o.err.rfind("vpm render: error: ", 0), 0u) << o.err;
    EXPECT_NE(o.err.find(needle), std::string::npos) << "'" << needle << "' not in: " << o.err;
    EXPECT_EQ(temporaries_in(dir.path), 0);
}

}  // namespace

TEST(OutputSafety, NonExrNameIsRefusedAndNothingIsWritten) {
    ScratchDir dir;
    write_file(dir.path / "s.toml", tiny_scene());
    expect_refused(dir, quote(dir.path / "s.toml") + " -o " + quote(dir.path / "img.png"), "ending in .exr");
    for (const char* f : {"img.png", "img.exr", "img.json"}) EXPECT_FALSE(fs::exists(dir.path / f)) << f;
    // Also from render.output in the config.
    write_file(dir.path / "o.toml", tiny_scene("output = \"" + dir.file("o.png") + "\"\n"));
    expect_refused(dir, quote(dir.path / "o.toml"), "ending in .exr");
    EXPECT_FALSE(fs::exists(dir.path / "o.png"));
}

TEST(OutputSafety, DevNullIsNeverReplaced) {
    ScratchDir dir;
    write_file(dir.path / "s.toml", tiny_scene());
    expect_refused(dir, quote(dir.path / "s.toml") + " -o /dev/null", "ending in .exr");
    // A name that ends in .exr but leads to a device through a symlink.
    fs::create_symlink("/dev/null", dir.path / "null.exr");
    expect_refused(dir, quote(dir.path / "s.toml") + " -o " + quote(dir.path / "null.exr"), "character device");
    struct stat st {};
    ASSERT_EQ(::stat("/dev/null", &st), 0);
    EXPECT_TRUE(S_ISCHR(st.st_mode)) << "/dev/null is no longer a device";
    EXPECT_FALSE(fs::exists("/dev/null.png"));
    EXPECT_FALSE(fs::exists("/dev/null.json"));
    EXPECT_TRUE(fs::is_symlink(dir.path / "null.exr"));
}

TEST(OutputSafety, FifoAndFolderAreRefused) {
    ScratchDir dir;
    write_file(dir.path / "s.toml", tiny_scene());
    ASSERT_EQ(::mkfifo((dir.path / "fifo.exr").c_str(), 0644), 0);
    expect_refused(dir, quote(dir.path / "s.toml") + " -o " + quote(dir.path / "fifo.exr"), "FIFO");
    EXPECT_EQ(fs::status(dir.path / "fifo.exr").type(), fs::file_type::fifo);
    // The sidecar's name taken by a folder is refused too, before the EXR is written.
    fs::create_directories(dir.path / "x.json");
    expect_refused(dir, quote(dir.path / "s.toml") + " -o " + quote(dir.path / "x.exr"), "a folder");
    EXPECT_FALSE(fs::exists(dir.path / "x.exr"));
}

TEST(OutputSafety, SymlinkIsWrittenThrough) {
    ScratchDir dir;
    write_file(dir.path / "s.toml", tiny_medium_scene());
    fs::create_directories(dir.path / "real");
    fs::create_symlink("real/target.exr", dir.path / "link.exr");   // relative, dangling for now
    const Outcome o = run_vpm("render -q " + quote(dir.path / "s.toml") + " -o " + quote(dir.path / "link.exr"), dir.path);
    ASSERT_EQ(o.code, 0) << o.err;
    EXPECT_TRUE(fs::is_symlink(dir.path / "link.exr")) << "the link was replaced by a file";
    ASSERT_TRUE(fs::is_regular_file(dir.path / "real" / "target.exr"));
    EXPECT_EQ(read_exr(dir.path / "link.exr").width, 4);
    EXPECT_TRUE(fs::is_regular_file(dir.path / "link.png"));
    EXPECT_TRUE(fs::is_regular_file(dir.path / "link.json"));
}

TEST(OutputSafety, UnwritableOutputFailsBeforeTheWork) {
    ScratchDir dir;
    write_file(dir.path / "s.toml", tiny_scene());
    write_file(dir.path / "file.txt", "a file, not a folder\n");
    // Without -q a render logs "load:", "render:" and "wrote" lines: none may come before the error.
    const Outcome o = run_vpm("render " + quote(dir.path / "s.toml") + " -o " + quote(dir.path / "file.txt" / "out.exr"),
                              dir.path);
    EXPECT_EQ(o.code, 1);
    EXPECT_TRUE(o.one_line()) << o.err;
    EXPECT_NE(o.err.find("file.txt"), std::string::npos) << o.err;
    EXPECT_EQ(o.err.find("load:"), std::string::npos) << o.err;
}

TEST(OutputSafety, StudyOutFolderCheckedBeforeTheWork) {
    ScratchDir dir;
    write_file(dir.path / "file.txt", "x\n");
    const Outcome o = run_vpm("study --out " + quote(dir.path / "file.txt" / "study") +
                                  " --trials 4 --dims 3 --k 4 --scenarios uniform --no-plots",
                              dir.path);
    EXPECT_EQ(o.code, 1) << o.err;
    EXPECT_TRUE(o.one_line()) << o.err;
    EXPECT_EQ(o.err.rfind("vpm study: error: ", 0), 0u) << o.err;
    EXPECT_EQ(o.err.find("study: uniform"), std::string::npos) << "the trials ran first:\n" << o.err;
}

TEST(OutputSafety, ConcurrentRunsLeaveOneRunsFiles) {
    // Two scenes that differ only in light intensity: the sidecar says which run wrote it, and
    // the EXR and PNG must be that run's (rendered once alone first, for comparison).
    ScratchDir dir;
    write_file(dir.path / "a.toml", tiny_medium_scene(2.0));
    write_file(dir.path / "b.toml", tiny_medium_scene(9.0));
    for (const char* s : {"a", "b"}) {
        const Outcome o = run_vpm("render -q --set render.width=32 --set render.height=32 " +
                                      quote(dir.path / (std::string(s) + ".toml")) + " -o " +
                                      quote(dir.path / (std::string("ref_") + s + ".exr")),
                                  dir.path);
        ASSERT_EQ(o.code, 0) << o.err;
    }
    const std::string exr_a = read_file(dir.path / "ref_a.exr"), exr_b = read_file(dir.path / "ref_b.exr");
    const std::string png_a = read_file(dir.path / "ref_a.png"), png_b = read_file(dir.path / "ref_b.png");
    ASSERT_NE(exr_a, exr_b);
    const std::string vpm = std::string("'") + VPM_BINARY + "' render -q --set render.width=32 --set render.height=32 ";
    const fs::path out = dir.path / "out.exr";
    for (int trial = 0; trial < 12; ++trial) {
        const std::string cmd = "cd " + quote(dir.path) + " && (" + vpm + "a.toml -o out.exr & " + vpm +
                                "b.toml -o out.exr & wait) 2> race.err";
        ASSERT_EQ(std::system(cmd.c_str()), 0);
        EXPECT_EQ(read_file(dir.path / "race.err"), "");
        const auto j = nlohmann::json::parse(read_file(dir.path / "out.json"));
        const double intensity = j["config"]["lights"][0]["intensity"][0].get<double>();
        const bool a = intensity == 2.0;
        ASSERT_TRUE(a || intensity == 9.0) << intensity;
        EXPECT_EQ(read_file(out), a ? exr_a : exr_b) << "trial " << trial << ": the EXR is not from the run of the sidecar";
        EXPECT_EQ(read_file(dir.path / "out.png"), a ? png_a : png_b) << "trial " << trial;
    }
    EXPECT_EQ(temporaries_in(dir.path), 0);
}

TEST(OutputSafety, SignalDuringAWriteRemovesTheTemporary) {
    // A child process stages a file (the temporary exists, the rename has not happened) and is
    // then hit by SIGTERM or SIGINT: it must die by that signal and leave no temporary behind.
    for (int sig : {SIGTERM, SIGINT}) {
        ScratchDir dir;
        const fs::path dest = dir.path / "big.exr";
        const pid_t pid = ::fork();
        ASSERT_GE(pid, 0);
        if (pid == 0) {
            remove_temporaries_on_signals();
            Image img(512, 512);
            StagedFile staged = stage_exr(dest, img);
            if (!fs::exists(staged.temp())) ::_exit(10);
            ::raise(sig);
            ::_exit(11);   // not reached: the handler re-raises with the default action
        }
        int status = 0;
        ASSERT_EQ(::waitpid(pid, &status, 0), pid);
        ASSERT_TRUE(WIFSIGNALED(status)) << "child exit code " << (WIFEXITED(status) ? WEXITSTATUS(status) : -1);
        EXPECT_EQ(WTERMSIG(status), sig);
        EXPECT_EQ(temporaries_in(dir.path), 0) << "signal " << sig;
        EXPECT_FALSE(fs::exists(dest));
    }
}

TEST(OutputSafety, NonFinitePixelsOfTheFinalImageAreCounted) {
    // Finite samples of a huge light sum to +Inf pixels: the sidecar must count them.
    ScratchDir dir;
    write_file(dir.path / "s.toml", tiny_medium_scene(1e308));
    const Outcome o = run_vpm("render -q " + quote(dir.path / "s.toml") + " -o " + quote(dir.path / "inf.exr"), dir.path);
    ASSERT_EQ(o.code, 0) << o.err;
    const Image img = read_exr(dir.path / "inf.exr");
    size_t bad = 0;
    for (size_t i = 0; i < img.rgb.size(); i += 3)
        bad += !(std::isfinite(img.rgb[i]) && std::isfinite(img.rgb[i + 1]) && std::isfinite(img.rgb[i + 2]));
    ASSERT_GT(bad, 0u) << "the scene no longer produces Inf pixels; pick a brighter light";
    const auto j = nlohmann::json::parse(read_file(dir.path / "inf.json"));
    EXPECT_EQ(j["render"]["nonfinite_pixels"].get<size_t>(), bad);
    EXPECT_NE(o.err.find("NaN or Inf"), std::string::npos) << "no warning: " << o.err;
}

TEST(OutputSafety, CompareRefusesNonFiniteImages) {
    ScratchDir dir;
    Image ref(8, 8), img(8, 8);
    for (auto& v : ref.rgb) v = 0.5f;
    img = ref;
    for (size_t i = 0; i < 30 * 3; ++i) img.rgb[i] = std::numeric_limits<float>::infinity();
    write_exr(dir.path / "img.exr", img);
    write_exr(dir.path / "ref.exr", ref);
    Outcome o = run_vpm("compare " + quote(dir.path / "img.exr") + " " + quote(dir.path / "ref.exr"), dir.path);
    EXPECT_EQ(o.code, 1) << o.out;
    EXPECT_TRUE(o.one_line()) << o.err;
    EXPECT_NE(o.err.find("30 of 64 pixels are NaN or Inf"), std::string::npos) << o.err;
    EXPECT_NE(o.err.find("img.exr"), std::string::npos) << o.err;
    // The same the other way round, and a clean pair still measures.
    o = run_vpm("compare " + quote(dir.path / "ref.exr") + " " + quote(dir.path / "img.exr"), dir.path);
    EXPECT_EQ(o.code, 1);
    o = run_vpm("compare " + quote(dir.path / "ref.exr") + " " + quote(dir.path / "ref.exr"), dir.path);
    EXPECT_EQ(o.code, 0) << o.err;
    EXPECT_NE(o.out.find("rmse 0"), std::string::npos) << o.out;
}

TEST(OutputSafety, SidecarLoadsAgainAsTheConfig) {
    ScratchDir dir;
    write_file(dir.path / "s.toml", tiny_medium_scene(3.0, "seed = 7\n"));
    Outcome o = run_vpm("render -q " + quote(dir.path / "s.toml") + " -o " + quote(dir.path / "first.exr"), dir.path);
    ASSERT_EQ(o.code, 0) << o.err;
    o = run_vpm("render -q " + quote(dir.path / "first.json") + " -o " + quote(dir.path / "second.exr"), dir.path);
    ASSERT_EQ(o.code, 0) << o.err;
    EXPECT_EQ(read_file(dir.path / "first.exr"), read_file(dir.path / "second.exr"));
    const auto a = nlohmann::json::parse(read_file(dir.path / "first.json"));
    auto b = nlohmann::json::parse(read_file(dir.path / "second.json"));
    b["config"]["render"]["output"] = a["config"]["render"]["output"];
    EXPECT_EQ(a["config"], b["config"]);
}
