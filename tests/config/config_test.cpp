// Config loading: each class of user error gives one message naming the file, line and key;
// --set overrides validate like the file; the resolved config round-trips.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "core/error.h"
#include "render/photon_map/photon_map_integrator.h"
#include "render/run/run_config.h"

using namespace vpm;

namespace {

const char* kMinimal = R"(
[render]
width = 8
height = 6
spp = 2

[camera]
position = [0, 0, 5]
look_at = [0, 0, 0]

[[lights]]
type = "point"
position = [0, 3, 0]
intensity = 10

[[media]]
type = "homogeneous"
shape = "sphere"
radius = 1.0
sigma_t_scale = 2.0
albedo = [0.9, 0.8, 0.7]
g = 0.3
)";

RunConfig build(const std::string& text, const std::vector<std::string>& overrides = {}) {
    return RunConfig::build(parse_config(text, "test.toml", ".", overrides));
}

// Builds and returns the ConfigError message ("" when no error).
std::string error_of(const std::string& text, const std::vector<std::string>& overrides = {}) {
    try {
        build(text, overrides);
    } catch (const ConfigError& e) {
        return e.what();
    }
    return "";
}

std::string with_line(std::string text, const std::string& after, const std::string& line) {
    const auto pos = text.find(after);
    EXPECT_NE(pos, std::string::npos);
    const auto eol = text.find('\n', pos);
    return text.insert(eol + 1, line + "\n");
}

std::string replace(std::string text, const std::string& from, const std::string& to) {
    const auto pos = text.find(from);
    EXPECT_NE(pos, std::string::npos) << from;
    return text.replace(pos, from.size(), to);
}

}  // namespace

TEST(Config, MinimalSceneBuilds) {
    auto config = build(kMinimal);
    EXPECT_EQ(config.render.width, 8);
    EXPECT_EQ(config.scene->media.size(), 1u);
    EXPECT_NEAR(config.scene->media[0]->albedo()[1], 0.8, 0);
    EXPECT_STREQ(config.integrator->name, "path");
}

TEST(Config, UnknownKeyNamesKeyAndLine) {
    const std::string text = with_line(kMinimal, "sigma_t_scale = 2.0", "sigma_s = 3");
    const std::string msg = error_of(text);
    EXPECT_NE(msg.find("test.toml:21"), std::string::npos) << msg;
    EXPECT_NE(msg.find("media.0.sigma_s"), std::string::npos) << msg;
    EXPECT_NE(msg.find("unknown key"), std::string::npos) << msg;
}

TEST(Config, UnknownTopLevelTable) {
    const std::string msg = error_of(std::string(kMinimal) + "\n[integrator]\nname = 1\n");
    EXPECT_NE(msg.find("integrator: unknown key"), std::string::npos) << msg;
}

TEST(Config, WrongTypeIsAnError) {
    const std::string msg = error_of(replace(kMinimal, "spp = 2", "spp = \"many\""));
    EXPECT_NE(msg.find("test.toml:5"), std::string::npos) << msg;
    EXPECT_NE(msg.find("render.spp: expected an integer, got a string"), std::string::npos) << msg;
}

TEST(Config, OutOfRangeValuesNameTheAllowedRange) {
    struct Case { const char* from; const char* to; const char* expect; };
    const Case cases[] = {
        {"sigma_t_scale = 2.0", "sigma_t_scale = -1.0", "media.0.sigma_t_scale: value -1 is out of range; allowed: >= 0"},
        {"g = 0.3", "g = 1.0", "media.0.g: value 1 is out of range; allowed: (-1, 1)"},
        {"g = 0.3", "g = -1.5", "media.0.g: value -1.5 is out of range; allowed: (-1, 1)"},
        {"albedo = [0.9, 0.8, 0.7]", "albedo = [0.9, 1.2, 0.7]", "media.0.albedo: component 1.2 is out of range; allowed: [0, 1]"},
        {"albedo = [0.9, 0.8, 0.7]", "albedo = -0.1", "media.0.albedo: component -0.1 is out of range"},
        {"width = 8", "width = 0", "render.width: value 0 is out of range; allowed: [1, 65536]"},
        {"height = 6", "height = -3", "render.height: value -3 is out of range"},
        {"type = \"point\"", "type = \"laser\"", "lights.0.type: unknown value \"laser\"; allowed: \"point\", \"spot\""},
    };
    for (const Case& c : cases) {
        const std::string msg = error_of(replace(kMinimal, c.from, c.to));
        EXPECT_NE(msg.find(c.expect), std::string::npos) << "got: " << msg << "\nexpected: " << c.expect;
        EXPECT_EQ(msg.rfind("test.toml:", 0), 0u) << msg;
    }
}

TEST(Config, ImageTooLargeForMemory) {
    const std::string msg = error_of(replace(replace(kMinimal, "width = 8", "width = 65536"), "height = 6", "height = 65536"));
    EXPECT_NE(msg.find("more than this machine's memory"), std::string::npos) << msg;
}

TEST(Config, MalformedTomlNamesTheLine) {
    const std::string msg = error_of(replace(kMinimal, "spp = 2", "spp = = 2"));
    EXPECT_NE(msg.find("test.toml:5: TOML syntax error"), std::string::npos) << msg;
}

TEST(Config, MissingFileIsAFileError) {
    EXPECT_THROW(RunConfig::load("/nonexistent/scene.toml"), FileError);
}

TEST(Config, CorrectedEstimatorRejectsKOne) {
    const std::string msg = error_of(std::string(kMinimal) + "\n[photons]\nestimator = \"corrected\"\nk = 1\n");
    EXPECT_NE(msg.find("photons.k: the corrected estimator needs k >= 2"), std::string::npos) << msg;
}

TEST(Config, SetOverridesAreAppliedAndValidated) {
    auto config = build(kMinimal, {"media.0.sigma_t_scale=10", "render.spp=64", "photons.k=8", "render.integrator=photon_map"});
    EXPECT_EQ(config.render.spp, 64);
    EXPECT_EQ(photon_map_settings(config).k, 8);
    EXPECT_STREQ(config.integrator->name, "photon_map");
    EXPECT_DOUBLE_EQ(config.scene->media[0]->sigma_t(Vec3::Zero()), 10.0);

    std::string msg = error_of(kMinimal, {"media.0.g=2"});
    EXPECT_NE(msg.find("--set media.0.g: media.0.g: value 2 is out of range"), std::string::npos) << msg;
    msg = error_of(kMinimal, {"media.3.g=0.1"});
    EXPECT_NE(msg.find("index 3 is past the end of 'media'"), std::string::npos) << msg;
    msg = error_of(kMinimal, {"render.sppp=3"});
    EXPECT_NE(msg.find("render.sppp: unknown key"), std::string::npos) << msg;
    msg = error_of(kMinimal, {"render.spp"});
    EXPECT_NE(msg.find("expected KEY=VALUE"), std::string::npos) << msg;
}

TEST(Config, ResolvedConfigRoundTrips) {
    auto first = build(kMinimal);
    const std::string resolved = first.resolved_toml();
    // Defaults are written out.
    EXPECT_NE(resolved.find("integrator = 'path'"), std::string::npos) << resolved;
    EXPECT_NE(resolved.find("fov = 40"), std::string::npos) << resolved;
    auto second = build(resolved);
    EXPECT_EQ(second.resolved_toml(), resolved);
}

TEST(Config, SceneWithoutLightsIsAnError) {
    const std::string text = replace(replace(replace(kMinimal, "[[lights]]", ""), "type = \"point\"", ""),
                                     "intensity = 10", "");
    const std::string msg = error_of(replace(text, "position = [0, 3, 0]", ""));
    EXPECT_NE(msg.find("no [[lights]]"), std::string::npos) << msg;
}

TEST(Config, HomogeneousSceneBuildsNeitherEmbreeNorOpenVdb) {
    auto config = build(kMinimal);
    EXPECT_FALSE(config.scene->uses_embree());
    EXPECT_FALSE(config.scene->uses_openvdb());
    bool said_embree = false, said_vdb = false;
    for (const auto& line : config.scene->build_log) {
        said_embree |= line == "Embree: not built (no shapes)";
        said_vdb |= line == "OpenVDB: not used (no grid media)";
    }
    EXPECT_TRUE(said_embree);
    EXPECT_TRUE(said_vdb);
}

TEST(Config, OnlyScenesWithShapesCreateAnEmbreeDevice) {
    const size_t before = Surfaces::devices_created();
    build(kMinimal);
    EXPECT_EQ(Surfaces::devices_created(), before);
    auto config = build(std::string(kMinimal) + "\n[[shapes]]\ntype = \"quad\"\ncenter = [0, -1, 0]\nu = [2, 0, 0]\nv = [0, 0, 2]\n");
    EXPECT_EQ(Surfaces::devices_created(), before + 1);
    EXPECT_TRUE(config.scene->uses_embree());
}

TEST(Config, BaseConfigIsMergedUnderTheIncludingFile) {
    const auto dir = std::filesystem::temp_directory_path() / ("vpm_config_base_test_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    {
        std::ofstream(dir / "base.toml") << kMinimal;
    }
    auto config = build("base = \"" + (dir / "base.toml").string() + "\"\n[render]\nspp = 5\n[photons]\nk = 9\n");
    EXPECT_EQ(config.render.spp, 5);
    EXPECT_EQ(config.render.width, 8);   // from the base
    EXPECT_EQ(photon_map_settings(config).k, 9);
    EXPECT_EQ(config.scene->media.size(), 1u);
    // An error in a key that came from the base names the base file and its line.
    {
        std::ofstream(dir / "bad.toml") << std::string(kMinimal) + "\n[photons]\nkk = 3\n";
    }
    const std::string msg = error_of("base = \"" + (dir / "bad.toml").string() + "\"\n");
    EXPECT_NE(msg.find("bad.toml:25: photons.kk: unknown key"), std::string::npos) << msg;
    EXPECT_NE(error_of("base = \"/nonexistent.toml\"\n").find("test.toml:1: base: cannot open"), std::string::npos);
    std::filesystem::remove_all(dir);
}
