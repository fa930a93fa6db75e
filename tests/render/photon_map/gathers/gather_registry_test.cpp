// The gather registry (render/photon_map/gathers/gather_registry.h): every gather a user can force
// runs and is recorded under the name the user wrote (run record, sweeps and Python read
// RunStats::gather_used), old names map to their entry, and the automatic plan measures exactly
// the entries marked plan_measures.
#include <gtest/gtest.h>

#include <set>
#include <string>

#include <nlohmann/json.hpp>

#include "render/photon_map/gathers/gather_registry.h"
#include "render/run/run.h"
#include "render/run/run_config.h"
#include "render/photon_map/photon_map_stats.h"

using namespace vpm;

TEST(GatherRegistry, EveryForcedGatherIsRecordedByItsOwnName) {
    for (const GatherEntry& e : gather_entries()) {
        if (e.chooses) continue;
        const RunConfig config = RunConfig::load(
            VPM_SOURCE_DIR "/configs/thin_cube.toml",
            {"render.width=8", "render.height=8", "render.spp=1", "render.time_limit=0", "photons.count=3000",
             "photons.k=8", "photons.beam_k=8", std::string("photons.gather=\"") + e.name + "\""});
        RunOptions o;
        o.progress = false;
        const RunResult r = run(config, o);
        ASSERT_TRUE(r.stats.gather_used) << e.name;
        EXPECT_EQ(*r.stats.gather_used, e.name);
        EXPECT_EQ(r.record.json().at("gather_used"), e.name);
    }
}

TEST(GatherRegistry, NamesAreUniqueAndOldNamesFindTheirEntry) {
    std::set<std::string> names;
    for (const GatherEntry& e : gather_entries()) {
        EXPECT_TRUE(names.insert(e.name).second) << e.name;
        EXPECT_EQ(&gather_entry(e.mode), &e);
        EXPECT_EQ(find_gather(e.name), &e);
    }
    ASSERT_NE(find_gather("beam"), nullptr);
    EXPECT_STREQ(find_gather("beam")->name, "point_beam");
    EXPECT_EQ(find_gather("beams"), nullptr);
}

TEST(GatherRegistry, TheAutomaticPlanMeasuresTheMarkedGathers) {
    const RunConfig config = RunConfig::load(VPM_SOURCE_DIR "/configs/thin_cube.toml",
                                             {"render.width=8", "render.height=8", "render.time_limit=1e-9",
                                              "photons.count=3000", "photons.k=8", "photons.gather=\"auto\""});
    RunOptions o;
    o.progress = false;
    const RunResult r = run(config, o);
    ASSERT_TRUE(PhotonMapStats::of(r.stats).auto_gather);
    std::set<std::string> measured, marked;
    for (const GatherMeasurement& m : PhotonMapStats::of(r.stats).auto_gather->candidates) measured.insert(m.name);
    for (const GatherEntry& e : gather_entries())
        if (e.plan_measures) marked.insert(e.name);
    EXPECT_EQ(measured, marked);
}
