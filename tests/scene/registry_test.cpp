// The light and medium registries: every registered name builds, and an unknown `type` is one
// error naming the key and listing every registered name.
#include <gtest/gtest.h>

#include <functional>
#include <map>
#include <set>

#include "core/error.h"
#include "scene/lights/light_registry.h"
#include "scene/media/medium_registry.h"

using namespace vpm;

namespace {

std::string error_of(const std::function<void(Params&)>& build, const std::string& text, const char* table) {
    auto doc = parse_config(text, "registry.toml", ".");
    toml::table resolved;
    Params root(doc, &resolved);
    auto tables = root.tables(table);
    try {
        build(tables.at(0));
    } catch (const ConfigError& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST(LightRegistry, ListsEveryTypeOnceAndBuildsEach) {
    const std::map<std::string, std::string> keys = {
        {"point", "position = [0, 1, 0]\nintensity = 1"},
        {"spot", "position = [0, 1, 0]\nlook_at = [0, 0, 0]\nintensity = 1"},
        {"directional", "direction = [0, -1, 0]\nirradiance = 1"},
        {"quad", "center = [0, 1, 0]\nu = [1, 0, 0]\nv = [0, 0, 1]\nradiance = 1"},
        {"sphere", "center = [0, 1, 0]\nradius = 0.5\nradiance = 1"},
        {"environment", "radiance = 1"},
    };
    std::set<std::string> seen;
    for (const LightType& t : light_types()) {
        EXPECT_TRUE(seen.insert(t.name).second) << t.name;
        ASSERT_TRUE(keys.count(t.name)) << "a light type without a test entry: " << t.name;
        const std::string text = "[[lights]]\ntype = '" + std::string(t.name) + "'\n" + keys.at(t.name) + "\n";
        EXPECT_EQ(error_of([](Params& p) { make_light(p); }, text, "lights"), "") << t.name;
    }
    EXPECT_EQ(seen.size(), keys.size());
}

TEST(LightRegistry, UnknownTypeListsTheRegisteredNames) {
    const std::string msg = error_of([](Params& p) { make_light(p); }, "[[lights]]\ntype = 'laser'\n", "lights");
    EXPECT_NE(msg.find("registry.toml:2"), std::string::npos) << msg;
    EXPECT_NE(msg.find("lights.0.type"), std::string::npos) << msg;
    for (const LightType& t : light_types()) EXPECT_NE(msg.find(t.name), std::string::npos) << msg;
}

TEST(LightRegistry, UnknownKeyOfAKnownTypeIsReported) {
    const std::string msg = error_of([](Params& p) { make_light(p); },
                                     "[[lights]]\ntype = 'point'\nposition = [0, 1, 0]\nintensity = 1\ncolour = 2\n", "lights");
    EXPECT_NE(msg.find("lights.0.colour: unknown key"), std::string::npos) << msg;
}

TEST(MediumRegistry, UnknownTypeListsTheRegisteredNames) {
    const std::string msg = error_of([](Params& p) { make_medium(p); }, "[[media]]\ntype = 'fog'\n", "media");
    EXPECT_NE(msg.find("media.0.type"), std::string::npos) << msg;
    for (const MediumType& t : medium_types()) EXPECT_NE(msg.find(t.name), std::string::npos) << msg;
}

TEST(MediumRegistry, HomogeneousNeedsNoOpenVdb) {
    auto doc = parse_config("[[media]]\ntype = 'homogeneous'\nshape = 'sphere'\nradius = 1\n", "registry.toml", ".");
    toml::table resolved;
    Params root(doc, &resolved);
    auto tables = root.tables("media");
    const MediumType* type = nullptr;
    const auto medium = make_medium(tables.at(0), &type);
    ASSERT_NE(type, nullptr);
    EXPECT_STREQ(type->name, "homogeneous");
    EXPECT_FALSE(type->uses_openvdb);
    EXPECT_DOUBLE_EQ(medium->sigma_t(Vec3::Zero()), 1.0);
}
