// vpm sweep and vpm study at the process level (issue 13): duplicate or conflicting axes are
// refused, the sidecars record the --threads limit (not the machine's cores), a one-repeat sweep
// prints no "nan", and --trials reaches every study scenario.
#include <gtest/gtest.h>

#include <cstdlib>

#include <nlohmann/json.hpp>

#include "support/vpm_process.h"

using namespace vpm::test;

namespace {

const char* kScene = R"(
[render]
width = 6
height = 6
spp = 1
seed = 3
[camera]
position = [0.0, 0.0, 4.0]
look_at = [0.0, 0.0, 0.0]
[[lights]]
type = "point"
position = [0.0, 3.0, 0.0]
intensity = 20.0
[[media]]
type = "homogeneous"
shape = "sphere"
center = [0.0, 0.0, 0.0]
radius = 1.0
sigma_t_scale = 2.0
albedo = 0.9
[photons]
count = 300
k = 8
)";

void expect_sweep_refused(const ScratchDir& dir, const std::string& axes, const std::vector<std::string>& needles) {
    write_file(dir.path / "sweep.toml", "scene = \"scene.toml\"\n[reference]\nspp = 2\n[axes]\n" + axes);
    const Outcome o = run_vpm("sweep --dry-run " + quote(dir.path / "sweep.toml"), dir.path);
    EXPECT_EQ(o.code, 1) << axes << "\n" << o.out << o.err;
    EXPECT_TRUE(o.one_line()) << o.err;
    for (const auto& n : needles) EXPECT_NE(o.err.find(n), std::string::npos) << "'" << n << "' not in: " << o.err;
}

}  // namespace

TEST(SweepCli, DuplicateValuesAndConflictingAxesAreRefused) {
    ScratchDir dir;
    write_file(dir.path / "scene.toml", kScene);
    expect_sweep_refused(dir, "k = [4, 8, 4]\n", {"sweep.toml:5:", "axes.k", "the value 4 is listed twice"});
    expect_sweep_refused(dir, "estimator = [\"classic\"]\n\"photons.estimator\" = [\"corrected\"]\n",
                         {"axes.photons.estimator", "as axes.estimator does already"});
    expect_sweep_refused(dir, "k = [8]\n\"photons.k\" = [16]\n", {"photons.k", "as axes.k does already"});
    // Equal as a scene though spelt differently: an integer and a float for a float key.
    expect_sweep_refused(dir, "\"media.0.g\" = [0, 0.0]\n", {"media.0.g = 0", "give the same scene"});
}

TEST(SweepCli, SidecarsRecordTheThreadLimitAndOneRepeatPrintsNoNan) {
    ScratchDir dir;
    write_file(dir.path / "scene.toml", kScene);
    write_file(dir.path / "sweep.toml",
               "scene = \"scene.toml\"\nrepeats = 1\n[reference]\nspp = 2\n[axes]\nk = [4, 8]\n");
    const fs::path out = dir.path / "out";
    const Outcome o = run_vpm("sweep -q --no-plots --threads 1 " + quote(dir.path / "sweep.toml") + " --out " + quote(out),
                              dir.path);
    ASSERT_EQ(o.code, 0) << o.err;
    EXPECT_EQ(nlohmann::json::parse(read_file(out / "sweep.json"))["threads"].get<int>(), 1);
    int references = 0;
    for (const auto& e : fs::directory_iterator(out / "references"))
        if (e.path().extension() == ".json") {
            ++references;
            EXPECT_EQ(nlohmann::json::parse(read_file(e.path()))["threads"].get<int>(), 1) << e.path();
        }
    EXPECT_EQ(references, 1);
    const std::string md = read_file(out / "summary.md");
    EXPECT_EQ(md.find(" nan"), std::string::npos) << md;   // (" ": "luminance" contains "nan")
    EXPECT_EQ(md.find(".png"), std::string::npos) << md;   // issue 24: --no-plots made none, so none is listed
}

TEST(StudyCli, TrialsReachEveryScenarioAndThreadsAreRecorded) {
    ScratchDir dir;
    const fs::path out = dir.path / "study";
    const Outcome o = run_vpm("study --quiet --no-plots --threads 1 --trials 40 --dims 3 --k 4 "
                              "--scenarios uniform,photon_map,photon_pass --photon-map-size 2000 --out " +
                                  quote(out),
                              dir.path);
    ASSERT_EQ(o.code, 0) << o.err;
    const auto j = nlohmann::json::parse(read_file(out / "study.json"));
    EXPECT_EQ(j["threads"].get<int>(), 1);
    // trials column per scenario: uniform all 40, photon_map a quarter, photon_pass a tenth.
    const std::string csv = read_file(out / "study.csv");
    auto trials_of = [&](const std::string& scenario) {
        const size_t p = csv.find("\n" + scenario + ",3,4,classic,");
        if (p == std::string::npos) return std::string("(no row)");
        std::string line = csv.substr(p + 1, csv.find('\n', p + 1) - p - 1);
        for (int field = 0; field < 5; ++field) line = line.substr(line.find(',') + 1);
        return line.substr(0, line.find(','));
    };
    EXPECT_EQ(trials_of("uniform"), "40") << csv;
    EXPECT_EQ(trials_of("photon_map"), "10") << csv;
    EXPECT_EQ(trials_of("photon_pass"), "4") << csv;
    EXPECT_NE(read_file(out / "study.md").find("photon_map: 10 estimates per k (--trials / 4"), std::string::npos);
}

TEST(PlotSweep, EveryKIsLabelledAndTheSceneIsNamed) {
    if (std::system("/usr/bin/python3 -c 'import matplotlib' > /dev/null 2>&1") != 0)
        GTEST_SKIP() << "/usr/bin/python3 with matplotlib (python3-matplotlib) is not installed";
    ScratchDir dir;
    write_file(dir.path / "sweep.json", "{\"scene\": \"/x/configs/default_photon_map.toml\"}");
    const std::string script =
        "import sys; sys.path.insert(0, '" VPM_SOURCE_DIR "/tools'); import plot_sweep as p\n"
        "import matplotlib.pyplot as plt\n"
        "fig, ax = plt.subplots(); ax.plot([4, 8, 16, 32, 64], [1, 2, 3, 4, 5], label='x')\n"
        "p.k_axis(ax, 'y', 't', [4, 8, 16, 32, 64]); fig.canvas.draw()\n"
        "labels = [t.get_text() for t in ax.get_xticklabels()]\n"
        "assert labels == ['4', '8', '16', '32', '64'], labels\n"
        "assert p.scene_name(sys.argv[1]) == 'default_photon_map.toml', p.scene_name(sys.argv[1])\n"
        "assert p.panels([{'k': '4'}], ['k'], 'default_photon_map.toml')[1] == ['default_photon_map.toml']\n";
    write_file(dir.path / "check.py", script);
    const std::string cmd = "/usr/bin/python3 " + quote(dir.path / "check.py") + " " + quote(dir.path) + " 2> " +
                            quote(dir.path / "err.txt");
    EXPECT_EQ(std::system(cmd.c_str()), 0) << read_file(dir.path / "err.txt");
}

// Issue 24: study options are checked before any work, as a bad command line (exit 2, one line):
// a run that cannot fit in memory (it ended in std::bad_alloc), k < 2 (exit 1 before), empty list
// items (accepted before) and a scenario listed twice (a confusing CLI11 message before).
TEST(StudyCli, BadOptionsAndRunsThatCannotFitAreOneUsageError) {
    ScratchDir dir;
    const fs::path out = dir.path / "study";
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"--scenarios kernels --k 3 --n 4000000000000 --trials 2", "--n <= "},
        {"--scenarios kernels --k 3 --n 1000 --trials 4000000000000", "--trials <= "},
        {"--scenarios photon_map --k 3 --photon-map-size 4000000000000", "--photon-map-size"},
        {"--k 1", "--k values must be >= 2"},
        {"--k -3", "--k"},
        {"--k 3,,5", "empty item"},
        {"--dims 3,3", "listed twice"},
        {"--scenarios kernels,kernels", "'kernels' is listed twice"},
        {"--scenarios uniform,nope", "--scenarios"},
        {"--trials 1", "--trials must be >= 2"},
        {"--trials -5", "--trials"},          // wrapped to 2^64 - 5 before
        {"--seed -1", "--seed"},              // ran the whole default study with seed 2^64 - 1
        {"--threads -1", "--threads"},
        {"--scenarios photon_map --k 3 --photon-map-size 3", "--photon-map-size (3) must exceed"},   // exit 1 after the output folder
    };
    for (const auto& [args, needle] : cases) {
        const Outcome o = run_vpm("study --quiet --no-plots --threads 1 " + args + " --out " + quote(out), dir.path);
        EXPECT_EQ(o.code, 2) << args << ": " << o.err;
        EXPECT_TRUE(o.one_line()) << args << ": " << o.err;
        EXPECT_NE(o.err.find(needle), std::string::npos) << args << ": " << o.err;
        EXPECT_FALSE(fs::exists(out)) << args;
    }
}

// Issue 46: a sweep with no k axis draws no empty legend (matplotlib warned on stderr), and the
// study names the plots it wrote.
TEST(PlotSweep, NoLibraryWarningsAndTheStudyListsItsPlots) {
    if (std::system("/usr/bin/python3 -c 'import matplotlib' > /dev/null 2>&1") != 0)
        GTEST_SKIP() << "/usr/bin/python3 with matplotlib (python3-matplotlib) is not installed";
    ScratchDir dir;
    write_file(dir.path / "scene.toml", kScene);
    write_file(dir.path / "sweep.toml",
               "scene = \"scene.toml\"\nrepeats = 1\n[reference]\nspp = 2\npath_spp = [1]\n[axes]\n\"media.0.g\" = [0.0, 0.5]\n");
    Outcome o = run_vpm("sweep --threads 1 " + quote(dir.path / "sweep.toml") + " --out " + quote(dir.path / "out"), dir.path);
    ASSERT_EQ(o.code, 0) << o.err;
    EXPECT_TRUE(fs::exists(dir.path / "out" / "error_vs_k.png"));
    // (matplotlib's "No artists with labels found to put in legend", or any Python warning)
    EXPECT_EQ(o.err.find("No artists"), std::string::npos) << o.err;
    EXPECT_EQ(o.err.find("Warning:"), std::string::npos) << o.err;
    const fs::path out = dir.path / "study";
    o = run_vpm("study --threads 1 --trials 40 --dims 3 --k 4,8 --scenarios uniform --out " + quote(out), dir.path);
    ASSERT_EQ(o.code, 0) << o.err;
    for (const char* plot : {"study_error_uniform.png", "study_mse_uniform.png"}) {
        EXPECT_TRUE(fs::exists(out / plot)) << plot;
        EXPECT_NE(o.err.find("study: plot " + (out / plot).string()), std::string::npos) << o.err;
    }
    EXPECT_EQ(o.err.find("No artists"), std::string::npos) << o.err;
}
