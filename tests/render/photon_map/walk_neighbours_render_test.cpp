// photons.neighbours = "walks" in the renderer (photon/estimate/walk_estimate.h): the key is read
// and its bad values and combinations refused with one clear error; the furnace (albedo 1, a
// walk of ~dozens of collisions per photon path) is unbiased with it, the same on 1 and 2 threads.
#include <gtest/gtest.h>

#include <tbb/task_arena.h>

#include <string>
#include <vector>

#include "core/error.h"
#include "render/photon_map/photon_map_integrator.h"
#include "render/photon_map/photon_map_settings.h"
#include "render/run/run.h"
#include "render/run/run_config.h"
#include "support/sample_statistics.h"

using namespace vpm;

namespace {

const char* kFurnace = VPM_SOURCE_DIR "/configs/uniform_furnace.toml";

std::string error_of(const std::vector<std::string>& sets) {
    try {
        RunConfig::load(kFurnace, sets);
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

RunResult furnace(std::vector<std::string> sets) {
    for (const char* s : {"render.width=16", "render.height=16", "photons.count=40000", "photons.k=8", "render.spp=12",
                          "render.passes=12"})
        sets.push_back(s);
    RunOptions o;
    o.progress = false;
    return run(RunConfig::load(kFurnace, sets), o);
}

}  // namespace

TEST(WalkNeighbours, KeyIsReadAndBadValuesAreOneClearError) {
    EXPECT_EQ(photon_map_settings(RunConfig::load(kFurnace, {})).neighbourhood, Neighbourhood::photons);
    EXPECT_EQ(photon_map_settings(RunConfig::load(kFurnace, {"photons.neighbours=\"walks\""})).neighbourhood,
              Neighbourhood::walks);
    const std::string bad = error_of({"photons.neighbours=\"walk\""});
    EXPECT_NE(bad.find("neighbours"), std::string::npos) << bad;
    EXPECT_NE(bad.find("walks"), std::string::npos) << bad;
    EXPECT_NE(bad.find("photons"), std::string::npos) << bad;
    const std::string mse = error_of({"photons.neighbours=\"walks\"", "photons.estimator=\"mse_optimal\""});
    EXPECT_NE(mse.find("\"classic\" or \"corrected\""), std::string::npos) << mse;
    const std::string lgo = error_of({"photons.neighbours=\"walks\"", "photons.clustering=\"leave_group_out\""});
    EXPECT_NE(lgo.find("leave_group_out"), std::string::npos) << lgo;
    const std::string beams = error_of({"photons.neighbours=\"walks\"", "photons.gather=\"photon_beams\""});
    EXPECT_NE(beams.find("photon_beams"), std::string::npos) << beams;
}

// 12 passes (independent photon maps): the pass means' mean within 3 standard errors of 0.5; 1 and 2
// threads give the same image.
TEST(WalkNeighbours, FurnaceIsUnbiasedAndTheSameOnAnyThreadCount) {
    RunResult one, two;
    tbb::task_arena(1).execute([&] { one = furnace({"photons.neighbours=\"walks\""}); });
    tbb::task_arena(2).execute([&] { two = furnace({"photons.neighbours=\"walks\""}); });
    ASSERT_EQ(one.stats.passes.size(), 12u);
    test::Sample u;
    for (const auto& p : one.stats.passes) u.add(p.image_mean);
    EXPECT_NEAR(u.mean(), 0.5, 3.0 * u.se()) << u.mean() << " +- " << u.se();
    EXPECT_EQ(one.image.mean(), two.image.mean());
}
