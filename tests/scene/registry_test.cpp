// The light and medium registries: every registered name builds, and an unknown `type` is one
// error naming the key and listing every registered name; every light type meets its contract
// (power() is the mean emitted power), and Scene::build's contract checks refuse what breaks it.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <map>
#include <set>

#include "core/error.h"
#include "scene/lights/light_registry.h"
#include "scene/media/medium_registry.h"
#include "scene/scene.h"

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

// Keys that build each registered light type; a new type without an entry fails the tests below.
const std::map<std::string, std::string>& light_test_keys() {
    static const std::map<std::string, std::string> keys = {
        {"point", "position = [0, 1, 0]\nintensity = 1"},
        {"spot", "position = [0, 1, 0]\nlook_at = [0, 0, 0]\nintensity = 1"},
        {"directional", "direction = [0, -1, 0]\nirradiance = 1"},
        {"quad", "center = [0, 1, 0]\nu = [1, 0, 0]\nv = [0, 0, 1]\nradiance = 1"},
        {"sphere", "center = [0, 1, 0]\nradius = 0.5\nradiance = 1"},
        {"environment", "radiance = 1"},
    };
    return keys;
}

struct ParsedTable {
    ParsedTable(const std::string& text, const char* table)
        : doc(parse_config(text, "registry.toml", ".")), root(doc, &resolved), tables(root.tables(table)) {}
    std::shared_ptr<ConfigDocument> doc;
    toml::table resolved;
    Params root;
    std::vector<Params> tables;
};

std::string contract_error(const std::function<void(const Params&)>& check) {
    ParsedTable t("[[media]]\ntype = 'homogeneous'\n", "media");
    try {
        check(t.tables.at(0));
    } catch (const ConfigError& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST(LightRegistry, ListsEveryTypeOnceAndBuildsEach) {
    const std::map<std::string, std::string>& keys = light_test_keys();
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

// The contract of light_registry.h: the mean of sample_emission's power is power(), for every
// registered type (lights at infinity after set_scene_bounds, as Scene::build calls it). 4 standard
// errors of the Monte Carlo mean, fixed seed; a relative floor of 1e-12 for lights whose every
// sample carries exactly the mean.
TEST(LightRegistry, EveryTypeEmitsItsPowerOnAverage) {
    Bounds3 scene_bounds;
    scene_bounds.extend(Vec3(-1, -0.5, -2));
    scene_bounds.extend(Vec3(2, 1.5, 1));
    for (const LightType& t : light_types()) {
        ASSERT_TRUE(light_test_keys().count(t.name)) << "a light type without a test entry: " << t.name;
        ParsedTable table("[[lights]]\ntype = '" + std::string(t.name) + "'\n" + light_test_keys().at(t.name) + "\n",
                          "lights");
        std::unique_ptr<Light> light = make_light(table.tables.at(0));
        light->set_scene_bounds(scene_bounds);
        const double expected = light->power()[1];
        ASSERT_TRUE(std::isfinite(expected) && expected > 0.0) << t.name;
        Rng rng(7, 3);
        const int n = 200000;
        double sum = 0.0, sum2 = 0.0;
        for (int i = 0; i < n; ++i) {
            const EmissionSample e = light->sample_emission(rng);
            ASSERT_TRUE(e.power.allFinite()) << t.name;
            ASSERT_NEAR(e.ray.dir.norm(), 1.0, 1e-9) << t.name;
            sum += e.power[1];
            sum2 += e.power[1] * e.power[1];
        }
        const double mean = sum / n, se = std::sqrt(std::max(0.0, sum2 / n - mean * mean) / n);
        EXPECT_NEAR(mean, expected, 4.0 * se + 1e-12 * expected) << t.name << ": se " << se;
    }
}

namespace {

// A medium that breaks the contract: density everywhere (a newcomer's infinite slab).
class UnboundedMedium : public Medium {
public:
    UnboundedMedium() : Medium(Rgb::Constant(0.5), 0.0) {}
    Bounds3 bounds() const override {
        Bounds3 b;
        b.lo = Vec3(-kInfinity, -1, -kInfinity);
        b.hi = Vec3(kInfinity, 1, kInfinity);
        return b;
    }
    double sample_free_flight(const Ray&, double, Rng&) const override { return kInfinity; }
    double transmittance(const Ray&, double, Rng&) const override { return 1.0; }
    double sigma_t(const Vec3&) const override { return 1.0; }
    void majorant_pieces(const Ray&, double, const MajorantVisitor&) const override {}
    void optical_depth_profile(const Ray&, double, OpticalDepthProfile& out) const override { out.reset(1.0); }
    std::string describe() const override { return "unbounded slab"; }
};

// A light whose power overflows (a radiance times a huge area).
class OverflowingLight : public Light {
public:
    bool sample_incident(const Vec3&, Rng&, LightSample&) const override { return false; }
    EmissionSample sample_emission(Rng&) const override { return {}; }
    Rgb power() const override { return Rgb::Constant(kInfinity); }
    std::string describe() const override { return "overflowing"; }
};

}  // namespace

TEST(SceneContract, UnboundedMediumIsOneErrorNamingTheTable) {
    const std::string msg = contract_error([](const Params& p) { check_medium_contract(UnboundedMedium(), p); });
    EXPECT_NE(msg.find("media.0.type"), std::string::npos) << msg;
    EXPECT_NE(msg.find("not a finite box"), std::string::npos) << msg;
    // Every registered medium meets it as configured by the shipped defaults.
    ParsedTable t("[[media]]\ntype = 'homogeneous'\nshape = 'sphere'\nradius = 1e30\n", "media");
    EXPECT_EQ(contract_error([&](const Params& p) { check_medium_contract(*make_medium(t.tables.at(0)), p); }), "");
}

TEST(SceneContract, NonFinitePowerIsOneErrorNamingTheTable) {
    const std::string msg = contract_error([](const Params& p) { check_light_contract(OverflowingLight(), p, "test"); });
    EXPECT_NE(msg.find("media.0.type"), std::string::npos) << msg;
    EXPECT_NE(msg.find("is not a finite double (test)"), std::string::npos) << msg;
}
