#include "render/run/run_record.h"

#include <nlohmann/json.hpp>

#include <atomic>
#include <regex>
#include <thread>

#include "core/error.h"
#include "core/progress.h"
#include "support/io_test_util.h"

namespace {

using namespace vpm;
using vpm_test::TempDirTest;
namespace fs = std::filesystem;

class RunRecordTest : public TempDirTest {};

TEST_F(RunRecordTest, WritesPhasesAndEnvironment) {
    const char* argv[] = {"vpm", "render", "scene.toml"};
    RunRecord rec = RunRecord::with_environment(3, argv, 3);
    rec.phase("load", 0.25);
    rec.phase("trace", 1.5);
    rec.set("config.seed", 42);
    rec.set("config.camera.fov", 45.0);
    rec.set("config.name", "smoke");
    rec.set("config.flags.fast", true);
    rec.set("config.count", uint64_t(1) << 40);
    rec.set("config.list", nlohmann::json::array({1, 2, 3}));
    rec.set("stats.nan_pixels", std::numeric_limits<double>::quiet_NaN());

    const fs::path out = dir_ / "out.exr";
    const fs::path side = sidecar_path_for(out);
    rec.write(side);
    EXPECT_EQ(entries(dir_), std::vector<std::string>{"out.json"});

    const nlohmann::json j = nlohmann::json::parse(slurp(side));
    EXPECT_DOUBLE_EQ(j["phases"]["load"]["seconds"].get<double>(), 0.25);
    EXPECT_DOUBLE_EQ(j["phases"]["trace"]["seconds"].get<double>(), 1.5);
    EXPECT_GT(j["phases"]["trace"]["peak_rss_bytes"].get<uint64_t>(), 0u);
    EXPECT_GT(j["peak_rss_bytes"].get<uint64_t>(), 0u);
    EXPECT_EQ(j["config"]["seed"].get<int>(), 42);
    EXPECT_DOUBLE_EQ(j["config"]["camera"]["fov"].get<double>(), 45.0);
    EXPECT_EQ(j["config"]["name"], "smoke");
    EXPECT_EQ(j["config"]["flags"]["fast"], true);
    EXPECT_EQ(j["config"]["count"].get<uint64_t>(), uint64_t(1) << 40);
    EXPECT_EQ(j["config"]["list"].size(), 3u);
    EXPECT_EQ(j["stats"]["nan_pixels"], "nan");
    EXPECT_EQ(j["threads"].get<int>(), 3);
    EXPECT_EQ(j["command_line"], nlohmann::json::array({"vpm", "render", "scene.toml"}));
    EXPECT_FALSE(j["git_revision"].get<std::string>().empty());
    EXPECT_FALSE(j["vpm_version"].get<std::string>().empty());
    EXPECT_FALSE(j["hostname"].get<std::string>().empty());
    EXPECT_GT(j["physical_memory_bytes"].get<uint64_t>(), 0u);
    EXPECT_TRUE(std::regex_match(j["date_utc"].get<std::string>(),
                                 std::regex(R"(\d{4}-\d\d-\d\dT\d\d:\d\d:\d\dZ)")))
        << j["date_utc"];
}

TEST_F(RunRecordTest, DefaultThreadsAndCopies) {
    RunRecord rec = RunRecord::with_environment();
    EXPECT_GT(rec.json()["threads"].get<int>(), 0);
    EXPECT_FALSE(rec.json().contains("command_line"));
    RunRecord copy = rec;
    copy.set("x", 1);
    EXPECT_FALSE(rec.json().contains("x"));
    rec.set("a", 1);
    rec.set("a.b", 2);   // replaces a scalar on the way with an object
    EXPECT_EQ(rec.json()["a"]["b"], 2);
}

TEST_F(RunRecordTest, WriteFailureThrowsFileError) {
    RunRecord rec;
    const fs::path p = dir_ / "missing" / "out.json";
    try {
        rec.write(p);
        FAIL() << "expected FileError";
    } catch (const FileError& e) {
        EXPECT_NE(std::string(e.what()).find(p.string()), std::string::npos) << e.what();
    }
}

TEST(RunRecordPaths, SidecarAndPreview) {
    EXPECT_EQ(sidecar_path_for("out.exr"), fs::path("out.json"));
    EXPECT_EQ(preview_path_for("out.exr"), fs::path("out.png"));
    EXPECT_EQ(sidecar_path_for("/a/b.c/render.v2.exr"), fs::path("/a/b.c/render.v2.json"));
    EXPECT_EQ(preview_path_for("dir/noext"), fs::path("dir/noext.png"));
}

TEST(ProgressAndMemory, PeakRssIsPositive) {
    std::vector<char> block(32 << 20, 1);   // touch 32 MB
    EXPECT_GE(peak_rss_bytes(), uint64_t(32) << 20);
    EXPECT_GT(physical_memory_bytes(), peak_rss_bytes());
    EXPECT_EQ(block[12345], 1);
}

TEST(ProgressAndMemory, ShortOrNonTerminalRunsAreSilent) {
    testing::internal::CaptureStderr();
    {
        Progress progress("trace", 6000);
        std::vector<std::thread> threads;
        for (int t = 0; t < 4; ++t)
            threads.emplace_back([&] { for (int i = 0; i < 1500; ++i) progress.advance(); });
        for (auto& th : threads) th.join();
        progress.done();
        progress.done();   // idempotent
    }
    Progress disabled("x", 10, false);
    disabled.advance(10);
    disabled.done();
    EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
    Timer timer;
    EXPECT_GE(timer.seconds(), 0.0);
}

}  // namespace
