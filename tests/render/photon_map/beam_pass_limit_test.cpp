// photons.gather = "photon_beams" under render.time_limit: the pass is sized from the pilots'
// counted work (render/photon_map/beam_pass_size.h), so the choice is the same on any thread count,
// takes fewer photons than photons.count where the pass would not fit, and a pinned count stays.
#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <string>
#include <vector>

#include "config/params.h"
#include "config/unset_key.h"
#include "render/run/run.h"
#include "render/run/run_config.h"
#include "render/photon_map/photon_map_stats.h"

using namespace vpm;

namespace {

RunResult render(int threads, const std::vector<std::string>& extra) {
    std::vector<std::string> sets = {"render.width=16", "render.height=16", "render.time_limit=0.05",
                                     "photons.gather=\"photon_beams\"", "photons.k=8",
                                     "render.threads=" + std::to_string(threads)};
    sets.insert(sets.end(), extra.begin(), extra.end());
    RunOptions o;
    o.progress = false;
    // Unpinned, as `vpm render --unset photons.count --unset render.spp` (a --set pins them again).
    const std::shared_ptr<ConfigDocument> doc = load_config(VPM_SOURCE_DIR "/configs/glass_sphere_fog.toml", sets);
    unset_key(*doc, "render.spp");
    const bool count_set = std::any_of(extra.begin(), extra.end(), [](const std::string& e) { return e.rfind("photons.count", 0) == 0; });
    if (!count_set) unset_key(*doc, "photons.count");
    return run(RunConfig::build(doc), o);
}

// Photons per pass: the maps' photons over the passes traced.
double photons_per_pass(const RunResult& r) {
    return double(PhotonMapStats::of(r.stats).photon_ledger->pass_maps) / double(PhotonMapStats::of(r.stats).photon_ledger->passes_traced);
}

bool has_phase(const RunResult& r, const std::string& name) {
    return std::any_of(r.stats.phases.begin(), r.stats.phases.end(), [&](const auto& p) { return p.name == name; });
}

}  // namespace

TEST(BeamPassLimit, SizedFromCountsTheSameOnOneAndTwoThreads) {
    for (const char* widths : {"balloon", "sample_point"}) {
        const std::string w = std::string("photons.beam_widths=\"") + widths + "\"";
        const RunResult a = render(1, {w}), b = render(2, {w});
        ASSERT_TRUE(PhotonMapStats::of(a.stats).photon_ledger.has_value() && PhotonMapStats::of(b.stats).photon_ledger.has_value());
        EXPECT_EQ(photons_per_pass(a), photons_per_pass(b)) << widths;
        EXPECT_LT(photons_per_pass(a), 100000.0) << widths;   // photons.count's default does not fit 0.05 s
        EXPECT_GE(photons_per_pass(a), 1024.0) << widths;     // the small pilot's photons: the least N
        EXPECT_EQ(a.stats.passes.front().spp, 1) << widths;
        EXPECT_TRUE(has_phase(a, "beam_pass_pilot")) << widths;
    }
}

TEST(BeamPassLimit, APinnedCountStaysAndWarns) {
    const RunResult r = render(2, {"photons.count=20000"});
    ASSERT_TRUE(PhotonMapStats::of(r.stats).photon_ledger.has_value());
    EXPECT_EQ(photons_per_pass(r), 20000.0);
    const bool warned = std::any_of(r.stats.warnings.begin(), r.stats.warnings.end(), [](const std::string& s) {
        return s.find("one photon_beams pass of 20000 photons") != std::string::npos;
    });
    EXPECT_TRUE(warned);
}
