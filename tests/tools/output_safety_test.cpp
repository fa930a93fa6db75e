// Output files at the process level (issue 13): what `vpm render -o` may replace, when it checks,
// what it leaves after a signal, and that concurrent runs leave one run's files.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <sys/file.h>
#include <sys/inotify.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <cstring>
#include <cmath>
#include <limits>

#include <nlohmann/json.hpp>

#include "render/run/image_io.h"
#include "render/run/run_outputs.h"
#include "render/run/staged_file.h"
#include "support/vpm_process.h"

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

// Blocks until a file whose name contains `needle` is created in the watched folder (inotify fd).
bool wait_for_creation(int fd, const char* needle) {
    alignas(inotify_event) char buf[4096];
    for (;;) {
        const ssize_t n = ::read(fd, buf, sizeof buf);
        if (n <= 0) return false;
        for (ssize_t i = 0; i < n;) {
            const auto* ev = reinterpret_cast<const inotify_event*>(buf + i);
            if (ev->len && std::strstr(ev->name, needle)) return true;
            i += ssize_t(sizeof(inotify_event) + ev->len);
        }
    }
}

// Starts `vpm render -q CONFIG -o OUT` at SIZE x SIZE pixels; stderr goes to /dev/null.
pid_t spawn_vpm_render(const std::string& config, const std::string& out, int size) {
    const std::string w = "render.width=" + std::to_string(size), h = "render.height=" + std::to_string(size);
    const pid_t pid = ::fork();
    if (pid == 0) {
        if (!::freopen("/dev/null", "w", stderr)) ::_exit(126);
        ::execl(VPM_BINARY, VPM_BINARY, "render", "-q", config.c_str(), "-o", out.c_str(), "--set", w.c_str(), "--set",
                h.c_str(), static_cast<char*>(nullptr));
        ::_exit(127);
    }
    return pid;
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

TEST(OutputSafety, PassesTableIsPartOfTheRunsFiles) {
    // --reference adds OUT.passes.csv: checked before the work and written with the others.
    ScratchDir dir;
    write_file(dir.path / "s.toml", tiny_medium_scene());
    Outcome o = run_vpm("render -q " + quote(dir.path / "s.toml") + " -o " + quote(dir.path / "ref.exr"), dir.path);
    ASSERT_EQ(o.code, 0) << o.err;
    fs::create_directories(dir.path / "r.passes.csv");
    expect_refused(dir, quote(dir.path / "s.toml") + " --reference " + quote(dir.path / "ref.exr") + " -o " +
                            quote(dir.path / "r.exr"),
                   "r.passes.csv");
    EXPECT_FALSE(fs::exists(dir.path / "r.exr"));
    fs::remove(dir.path / "r.passes.csv");
    o = run_vpm("render -q " + quote(dir.path / "s.toml") + " --reference " + quote(dir.path / "ref.exr") + " -o " +
                    quote(dir.path / "r.exr"),
                dir.path);
    ASSERT_EQ(o.code, 0) << o.err;
    EXPECT_NE(read_file(dir.path / "r.passes.csv").find("pass,spp,elapsed_s"), std::string::npos);
}

// Issue 61: an image written through a link parted from its preview and sidecar (written beside
// the link, named after it). The link is refused before the work, naming its target.
TEST(OutputSafety, SymlinkAsTheImageIsRefused) {
    ScratchDir dir;
    write_file(dir.path / "s.toml", tiny_medium_scene());
    fs::create_directories(dir.path / "real");
    fs::create_symlink("real/target.exr", dir.path / "link.exr");   // relative, dangling for now
    const Outcome o = run_vpm("render -q " + quote(dir.path / "s.toml") + " -o " + quote(dir.path / "link.exr"), dir.path);
    EXPECT_EQ(o.code, 1) << o.err;
    EXPECT_TRUE(o.one_line()) << o.err;
    EXPECT_NE(o.err.find("symbolic link"), std::string::npos) << o.err;
    EXPECT_NE(o.err.find("real/target.exr"), std::string::npos) << o.err;
    EXPECT_TRUE(fs::is_symlink(dir.path / "link.exr"));
    EXPECT_FALSE(fs::exists(dir.path / "real" / "target.exr"));
    EXPECT_FALSE(fs::exists(dir.path / "link.png"));
    EXPECT_FALSE(fs::exists(dir.path / "link.json"));
    // The target itself is written, with its preview and sidecar beside it.
    const Outcome direct = run_vpm("render -q " + quote(dir.path / "s.toml") + " -o " + quote(dir.path / "real" / "target.exr"),
                                   dir.path);
    ASSERT_EQ(direct.code, 0) << direct.err;
    EXPECT_EQ(read_exr(dir.path / "link.exr").width, 4);
    EXPECT_TRUE(fs::is_regular_file(dir.path / "real" / "target.png"));
    EXPECT_TRUE(fs::is_regular_file(dir.path / "real" / "target.json"));
}

// Issue 61: a name too long for its temporary failed only after the render; -o '' fell back to
// render.output silently. Both are refused before the work.
TEST(OutputSafety, OverLongAndEmptyNamesAreRefusedBeforeTheWork) {
    ScratchDir dir;
    write_file(dir.path / "s.toml", tiny_scene());
    const std::string long_name = std::string(240, 'a') + ".exr";   // fits NAME_MAX (255), its temporary does not
    const Outcome o = run_vpm("render " + quote(dir.path / "s.toml") + " -o " + quote(dir.path / long_name), dir.path);
    EXPECT_EQ(o.code, 1) << o.err;
    EXPECT_TRUE(o.one_line()) << o.err;
    EXPECT_NE(o.err.find("bytes"), std::string::npos) << o.err;
    EXPECT_EQ(o.err.find("load:"), std::string::npos) << o.err;   // before the work
    const Outcome empty = run_vpm("render " + quote(dir.path / "s.toml") + " -o ''", dir.path);
    EXPECT_EQ(empty.code, 2) << empty.err;
    EXPECT_NE(empty.err.find("-o"), std::string::npos) << empty.err;
    EXPECT_NE(empty.err.find("empty"), std::string::npos) << empty.err;
    EXPECT_FALSE(fs::exists(dir.path / "out"));
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
    // the EXR and PNG must be that run's (rendered once alone first, for comparison). End to end;
    // with the old one-file-at-a-time renames about half the runs of this test caught a mixed set,
    // RenamesWaitForTheFolderLock below checks the mechanism deterministically.
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
    // A light of 1e308 summed to +Inf pixels; it is now refused before any work (issue 24: emission
    // at most 1e30, scene/lights/light_registry.h), so the counting is checked on an image directly.
    ScratchDir dir;
    write_file(dir.path / "s.toml", tiny_medium_scene(1e308));
    const Outcome o = run_vpm("render -q " + quote(dir.path / "s.toml") + " -o " + quote(dir.path / "inf.exr"), dir.path);
    EXPECT_EQ(o.code, 1) << o.err;
    EXPECT_TRUE(o.one_line()) << o.err;
    EXPECT_NE(o.err.find("lights.0.intensity"), std::string::npos) << o.err;
    EXPECT_FALSE(fs::exists(dir.path / "inf.exr"));
    Image img(3, 2);
    img.rgb[1] = std::numeric_limits<float>::infinity();
    img.rgb[9] = std::numeric_limits<float>::quiet_NaN();
    img.rgb[10] = std::numeric_limits<float>::infinity();
    EXPECT_EQ(count_nonfinite_pixels(img), 2u);
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

TEST(OutputSafety, SigtermWhileVpmWritesLeavesNoTemporary) {
    // The real binary: inotify wakes the test the moment vpm creates its first temporary (the
    // EXR of a 1024x1024 image, whose ZIP encoding alone takes far longer than a signal needs to
    // arrive), and the test sends SIGTERM at once. No sleeps, no polling.
    ScratchDir dir;
    write_file(dir.path / "s.toml", tiny_medium_scene());
    const fs::path out_dir = dir.path / "out";
    fs::create_directories(out_dir);
    const int fd = ::inotify_init1(IN_CLOEXEC);
    ASSERT_GE(fd, 0);
    ASSERT_GE(::inotify_add_watch(fd, out_dir.c_str(), IN_CREATE), 0);
    const std::string out = (out_dir / "big.exr").string();
    const pid_t pid = spawn_vpm_render(dir.file("s.toml"), out, 1024);
    ASSERT_GT(pid, 0);
    const bool signalled = wait_for_creation(fd, ".tmp-");
    if (signalled) ::kill(pid, SIGTERM);
    ::close(fd);
    int status = 0;
    ASSERT_EQ(::waitpid(pid, &status, 0), pid);
    ASSERT_TRUE(signalled);
    ASSERT_TRUE(WIFSIGNALED(status)) << "vpm finished before the signal arrived (exit "
                                     << (WIFEXITED(status) ? WEXITSTATUS(status) : -1) << ")";
    EXPECT_EQ(WTERMSIG(status), SIGTERM);
    EXPECT_EQ(temporaries_in(dir.path), 0);
    EXPECT_FALSE(fs::exists(out));
}

TEST(OutputSafety, RenamesWaitForTheFolderLock) {
    // A reader holding the folder's lock (as README tells readers to) sees no file of a run
    // replaced until it lets go, even once all three temporaries are written; then all three
    // appear. Deterministic: inotify reports the sidecar's temporary, the last one staged.
    ScratchDir dir;
    write_file(dir.path / "s.toml", tiny_medium_scene());
    const fs::path out_dir = dir.path / "out";
    fs::create_directories(out_dir);
    const int lock = ::open(out_dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    ASSERT_GE(lock, 0);
    ASSERT_EQ(::flock(lock, LOCK_EX), 0);
    const int fd = ::inotify_init1(IN_CLOEXEC);
    ASSERT_GE(fd, 0);
    ASSERT_GE(::inotify_add_watch(fd, out_dir.c_str(), IN_CREATE), 0);
    const pid_t pid = spawn_vpm_render(dir.file("s.toml"), (out_dir / "r.exr").string(), 16);
    ASSERT_GT(pid, 0);
    const bool staged = wait_for_creation(fd, "r.json.tmp-");
    ::close(fd);
    EXPECT_TRUE(staged);
    for (const char* f : {"r.exr", "r.png", "r.json"}) EXPECT_FALSE(fs::exists(out_dir / f)) << f << " replaced under the lock";
    ::close(lock);   // releases the lock
    int status = 0;
    ASSERT_EQ(::waitpid(pid, &status, 0), pid);
    ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << status;
    for (const char* f : {"r.exr", "r.png", "r.json"}) EXPECT_TRUE(fs::is_regular_file(out_dir / f)) << f;
}
