// The fuzz_config seeds (fuzz/corpus/config) as a regression test that runs without clang: each
// goes through parse_config + RunConfig::build exactly as the fuzz target does, and must either build
// or fail with a vpm::Error (a message for the user), never crash or throw anything else.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "core/error.h"
#include "render/run/run_config.h"
#include "config/config_file.h"
#include "config/params.h"

namespace fs = std::filesystem;
using namespace vpm;

namespace {

// "" when it builds, else the vpm::Error message.
std::string outcome(const std::string& text, const std::string& name) {
    try {
        const RunConfig config = RunConfig::build(parse_config(text, name, fs::temp_directory_path()));
        (void)config.resolved_toml();
        return "";
    } catch (const Error& e) {
        return e.what();
    }
}

}  // namespace

TEST(FuzzCorpus, ConfigSeedsBuildOrFailWithAMessage) {
    int seeds = 0;
    for (const auto& e : fs::directory_iterator(VPM_SOURCE_DIR "/fuzz/corpus/config")) {
        std::ifstream f(e.path(), std::ios::binary);
        std::stringstream s;
        s << f.rdbuf();
        const std::string name = e.path().filename().string();
        const std::string msg = outcome(s.str(), name);
        if (name.rfind("deep_", 0) == 0) {
            EXPECT_NE(msg.find("nesting deeper than 64"), std::string::npos) << name << ": " << msg;
        }
        if (name == "nesting_at_limit.toml") {
            EXPECT_EQ(msg.find("nesting deeper"), std::string::npos) << msg;
        }
        if (name == "sidecar_config.json") {
            EXPECT_EQ(msg, "") << msg;
        }
        ++seeds;
    }
    EXPECT_GE(seeds, 12);
}

TEST(FuzzCorpus, FortyThousandLevelHeaderIsAnErrorNotACrash) {
    std::string deep = "[a";
    for (int i = 1; i < 40000; ++i) deep += ".a";
    deep += "]\n";
    EXPECT_NE(outcome(deep, "deep.toml").find("deep.toml:1: nesting deeper than 64"), std::string::npos);
    // Exactly at the limit it still parses (and then fails as a scene without lights).
    std::string ok = "[a";
    for (int i = 1; i < kMaxConfigNesting; ++i) ok += ".a";
    ok += "]\n";
    EXPECT_EQ(outcome(ok, "ok.toml").find("nesting deeper"), std::string::npos);
}
