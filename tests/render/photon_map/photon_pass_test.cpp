// The memory-budget warning of the photon pass: before the kd-tree is built, a photon map projected to
// exceed photons.memory_budget_fraction of physical memory is announced in the log, with the
// projected size, and the projection and budget go into the run record (sidecar).
#include <gtest/gtest.h>

#include <sys/resource.h>

#include <nlohmann/json.hpp>
#include <sstream>

#include "core/error.h"
#include "core/progress.h"
#include "render/run/run.h"
#include "scene/scene.h"
#include "render/photon_map/gathers/photon_beams_gather_stats.h"

using namespace vpm;

namespace {

RunConfig small_scene(const std::string& fraction, const std::string& photons_extra = "") {
    const std::string text = R"(
[render]
width = 8
height = 8
spp = 1
integrator = "photon_map"
[camera]
position = [0, 0, 0]
look_at = [0, 0, -1]
fov = 90
[photons]
count = 2000
direct = "photon_map"
memory_budget_fraction = )" + fraction + "\n" + photons_extra + R"(
[[lights]]
type = "environment"
radiance = 0.5
[[media]]
type = "homogeneous"
shape = "sphere"
radius = 2
sigma_t_scale = 1.0
albedo = 0.9
)";
    return RunConfig::build(parse_config(text, "budget.toml", "."));
}

RunResult run_logged(const RunConfig& config, std::string& log) {
    std::ostringstream s;
    RunOptions o;
    o.progress = false;
    o.log = &s;
    RunResult r = run(config, o);
    log = s.str();
    return r;
}

}  // namespace

TEST(MemoryBudget, TinyBudgetWarnsWithProjectedSize) {
    const RunConfig config = small_scene("1e-12");   // ~24 GB * 1e-12: a few dozen bytes
    std::string log;
    const RunResult r = run_logged(config, log);
    const auto& j = r.record.json();
    const double stored = j.at("photons").at("stored").get<double>();
    ASSERT_GT(stored, 0.0);
    EXPECT_TRUE(j["photons"]["over_memory_budget"].get<bool>());
    const double projected = j["photons"]["projected_map_bytes"].get<double>();
    EXPECT_GE(projected, stored * 24.0);   // at least the records
    // the projection is not below what was actually built
    EXPECT_GE(projected, j["photons"]["map_bytes"].get<double>());
    EXPECT_NE(log.find("warning: the photon map will take about"), std::string::npos) << log;
    EXPECT_NE(log.find("photons.memory_budget_fraction"), std::string::npos) << log;
    // the warning comes before the build line
    EXPECT_LT(log.find("warning:"), log.find("build:")) << log;
}

TEST(MemoryBudget, DefaultBudgetDoesNotWarn) {
    const RunConfig config = small_scene("0.5");
    std::string log;
    const RunResult r = run_logged(config, log);
    EXPECT_FALSE(r.record.json()["photons"]["over_memory_budget"].get<bool>());
    EXPECT_EQ(log.find("warning:"), std::string::npos) << log;
}

TEST(MemoryBudget, FractionOutOfRangeIsAConfigError) {
    EXPECT_THROW(small_scene("0"), Error);
    EXPECT_THROW(small_scene("1.5"), Error);
}

// Photon beams are in the projection: with photons.gather = "photon_beams" no point photon is
// stored, and the projection counted only those (0 bytes, never over any budget).
TEST(MemoryBudget, PhotonBeamsAreInTheProjection) {
    const RunConfig config = small_scene("1e-12", "gather = \"photon_beams\"");
    std::string log;
    const RunResult r = run_logged(config, log);
    const auto& j = r.record.json();
    ASSERT_TRUE(r.stats.sections.find<PhotonBeamsGatherStats>() != nullptr);
    ASSERT_GT(r.stats.sections.find<PhotonBeamsGatherStats>()->recorded, 0u);
    EXPECT_TRUE(j["photons"]["over_memory_budget"].get<bool>());
    // not below the beams' BVH and records that were built
    EXPECT_GE(j["photons"]["projected_map_bytes"].get<double>(), double(r.stats.sections.find<PhotonBeamsGatherStats>()->bvh_bytes));
    EXPECT_NE(log.find("photon beams' BVH will take about"), std::string::npos) << log;
}

// The memory guards compare with what this process may use: an address-space limit (ulimit -v) below
// the physical memory is the limit (a 1e7-photon beam run under ulimit -v 10 GB was refused with a
// count that fits 25 GB, then died of std::bad_alloc).
TEST(MemoryBudget, AddressSpaceLimitBoundsTheMemoryLimit) {
    struct rlimit saved {};
    ASSERT_EQ(::getrlimit(RLIMIT_AS, &saved), 0);
    const uint64_t physical = physical_memory_bytes();
    ASSERT_GT(physical, 0u);
    uint64_t lower = physical / 2;
    if (saved.rlim_cur != RLIM_INFINITY) lower = std::min<uint64_t>(lower, uint64_t(saved.rlim_cur) / 2);
    struct rlimit limited = saved;
    limited.rlim_cur = rlim_t(lower);
    ASSERT_EQ(::setrlimit(RLIMIT_AS, &limited), 0);
    const uint64_t limit = memory_limit_bytes();
    ASSERT_EQ(::setrlimit(RLIMIT_AS, &saved), 0);
    EXPECT_GT(limit, 0u);
    EXPECT_LE(limit, lower);
    EXPECT_LE(memory_limit_bytes(), physical);
}
