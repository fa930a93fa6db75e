// One error format for every subcommand (issue 13): a bad command line prints exactly one line
// "vpm <cmd>: error: ... (see vpm <cmd> --help)" and exits 2; --version; defaults in --help.
#include <gtest/gtest.h>

#include "support/vpm_process.h"

using namespace vpm::test;

TEST(CliErrors, BadCommandLinesGiveOneLineAndExitCode2) {
    ScratchDir dir;
    write_file(dir.path / "s.toml", tiny_scene());
    const std::string cfg = quote(dir.path / "s.toml");
    const struct {
        std::string args, prefix;
    } cases[] = {
        {"render --threads abc " + cfg, "vpm render: error: "},
        {"render " + cfg + " -o a.exr -o b.exr", "vpm render: error: "},
        {"render " + cfg + " --no-such-flag", "vpm render: error: "},
        {"render", "vpm render: error: "},
        {"study --trials many", "vpm study: error: "},
        {"study --dims x", "vpm study: error: "},
        {"sweep", "vpm sweep: error: "},
        {"sweep merge", "vpm sweep: error: "},
        {"compare only_one.exr", "vpm compare: error: "},
        {"stress --bogus", "vpm stress: error: "},
        {"stress --quick --only zzz --out " + quote(dir.path / "st"), "vpm stress: error: "},   // issue 24: ran 0 cells, "all ok"
        {"study --k 1", "vpm study: error: "},                                               // issue 24: exit 1 before
        {"study --k 3,,5", "vpm study: error: "},                                            // issue 24: accepted before
        {"bench", "vpm bench: error: "},
        {"bench nope", "vpm bench: error: "},
        {"bench equal-time --size 12", "vpm bench: error: "},
        {"make-media --bogus", "vpm make-media: error: "},
        {"make-media", "vpm make-media: error: "},                                           // issue 47: rewrote ./media
        {"bench matrix --only zzz --no-plot --out " + quote(dir.path / "m"), "vpm bench: error: "},   // issue 47: exit 0
        {"bench matrix --budget nan --out " + quote(dir.path / "m"), "vpm bench: error: "},   // issue 47: accepted
        {"bench matrix --reference-seconds nan --out " + quote(dir.path / "m"), "vpm bench: error: "},
        {"bench matrix --max-tau -1 --out " + quote(dir.path / "m"), "vpm bench: error: "},
        {"sweep " + cfg + " --max-runs -1", "vpm sweep: error: "},                              // issue 47: ran all
        {"make-sky --width 1", "vpm make-sky: error: "},
        {"make-sky --out sky.png", "vpm make-sky: error: "},
        {"merge", "vpm merge: error: "},
        {"no-such-command", "vpm: error: "},
        {"", "vpm: error: "},
    };
    for (const auto& c : cases) {
        const Outcome o = run_vpm(c.args, dir.path);
        EXPECT_EQ(o.code, 2) << c.args << "\n" << o.err;
        EXPECT_TRUE(o.one_line()) << c.args << "\n" << o.err;
        EXPECT_EQ(o.err.rfind(c.prefix, 0), 0u) << c.args << "\n" << o.err;
        EXPECT_NE(o.err.find("--help"), std::string::npos) << c.args << "\n" << o.err;
    }
}

TEST(CliErrors, BadInputExitsWith1AndSuccessWith0) {
    ScratchDir dir;
    write_file(dir.path / "s.toml", tiny_scene());
    write_file(dir.path / "bad.toml", tiny_scene("widht = 3\n"));
    EXPECT_EQ(run_vpm("render -q " + quote(dir.path / "bad.toml") + " -o " + quote(dir.path / "o.exr"), dir.path).code, 1);
    EXPECT_EQ(run_vpm("render -q " + quote(dir.path / "s.toml") + " -o " + quote(dir.path / "o.exr"), dir.path).code, 0);
    // --set before the config argument takes one value each and leaves the config alone.
    const Outcome o = run_vpm("render -q --set render.spp=2 --set render.width=3 " + quote(dir.path / "s.toml") + " -o " +
                                  quote(dir.path / "p.exr"),
                              dir.path);
    EXPECT_EQ(o.code, 0) << o.err;
}

TEST(CliErrors, Version) {
    ScratchDir dir;
    const Outcome o = run_vpm("--version", dir.path);
    EXPECT_EQ(o.code, 0);
    EXPECT_EQ(o.out.rfind("vpm ", 0), 0u) << o.out;
    EXPECT_NE(o.out.find("(git "), std::string::npos) << o.out;
}

TEST(CliErrors, HelpShowsDefaultsAndExitCodes) {
    ScratchDir dir;
    Outcome o = run_vpm("stress --help", dir.path);
    EXPECT_EQ(o.code, 0);
    EXPECT_NE(o.out.find("out/stress"), std::string::npos) << o.out;
    EXPECT_NE(o.out.find("configs/stress"), std::string::npos) << o.out;
    o = run_vpm("bench equal-time --help", dir.path);
    EXPECT_EQ(o.code, 0);
    for (const char* d : {"1024", "1000000", "out/equal_time", "128x128"})
        EXPECT_NE(o.out.find(d), std::string::npos) << d << " not in:\n" << o.out;
    o = run_vpm("--help", dir.path);
    EXPECT_EQ(o.code, 0);
    EXPECT_NE(o.out.find("exit codes"), std::string::npos) << o.out;
}
