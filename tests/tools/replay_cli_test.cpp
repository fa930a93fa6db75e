// `vpm render OUT.json` renders the run record's image again, bit for bit, also for a run whose pass
// count came from render.time_limit's clock: the record sets render.time_limit_passes to the passes
// taken and lists the keys the document left unset (config_defaults), so the replay makes the plan's
// automatic choices again and renders the same passes without the clock, on another thread count.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "render/run/image_io.h"
#include "support/vpm_process.h"

using namespace vpm::test;

namespace {

// A small lit sphere of fog; render.spp and render.passes are left to the plan (photons.count, a pin,
// keeps the passes small enough for several in the limit).
std::string fog_scene(const std::string& integrator, double time_limit) {
    return "[render]\nwidth = 16\nheight = 12\nintegrator = \"" + integrator + "\"\ntime_limit = " +
           std::to_string(time_limit) +
           "\n[camera]\nposition = [0.0, 0.0, 4.0]\nlook_at = [0.0, 0.0, 0.0]\nfov = 40\n"
           "[[lights]]\ntype = \"point\"\nposition = [0.0, 2.0, 2.0]\nintensity = 10.0\n"
           "[[media]]\ntype = \"homogeneous\"\nshape = \"sphere\"\ncenter = [0.0, 0.0, 0.0]\nradius = 1.0\n"
           "sigma_t_scale = 2.0\nalbedo = 0.9\n[photons]\ncount = 4000\n";
}

nlohmann::json read_json(const fs::path& p) { return nlohmann::json::parse(read_file(p)); }

// Renders `scene` under its time limit on 2 threads, then its record on 1, and compares.
void expect_replay_is_bit_for_bit(const std::string& scene_text) {
    ScratchDir dir;
    write_file(dir.path / "scene.toml", scene_text);
    Outcome o = run_vpm("render " + quote(dir.path / "scene.toml") + " --threads 2 -o " + quote(dir.path / "a.exr"), dir.path);
    ASSERT_EQ(o.code, 0) << o.err;
    const nlohmann::json a = read_json(dir.path / "a.json");
    const int64_t passes = a["passes"]["count"].get<int64_t>();
    EXPECT_EQ(a["config"]["render"]["time_limit_passes"].get<int64_t>(), passes);
    // Defaults written back would pin the plan's choices: they are listed, and not read as pins.
    const nlohmann::json& defaults = a["config_defaults"];
    EXPECT_NE(std::find(defaults.begin(), defaults.end(), "render.spp"), defaults.end()) << defaults.dump();
    EXPECT_EQ(std::find(defaults.begin(), defaults.end(), "render.time_limit_passes"), defaults.end());

    o = run_vpm("render " + quote(dir.path / "a.json") + " --threads 1 -o " + quote(dir.path / "b.exr"), dir.path);
    ASSERT_EQ(o.code, 0) << o.err;
    EXPECT_EQ(o.err.find("pin: render."), std::string::npos) << o.err;   // the scene's one pin is photons.count
    EXPECT_NE(o.err.find("passes: " + std::to_string(passes) + ", render.time_limit_passes"), std::string::npos) << o.err;
    const nlohmann::json b = read_json(dir.path / "b.json");
    EXPECT_EQ(b["threads"].get<int>(), 1);
    EXPECT_EQ(b["passes"]["count"], a["passes"]["count"]);
    EXPECT_EQ(b["passes"]["spp_per_pass"], a["passes"]["spp_per_pass"]);
    EXPECT_EQ(b["integrator_used"], a["integrator_used"]);
    EXPECT_EQ(b.value("gather_used", ""), a.value("gather_used", ""));
    if (a.contains("photons")) {
        EXPECT_EQ(b["photons"]["traced"], a["photons"]["traced"]);   // photons per pass, and in the pilot and probe
        EXPECT_EQ(b["photons"]["auto_gather"]["count"], a["photons"]["auto_gather"]["count"]);
        EXPECT_EQ(b["photons"]["auto_gather"]["spp"], a["photons"]["auto_gather"]["spp"]);
    }
    nlohmann::json ca = a["config"], cb = b["config"];   // all but where it went and on how many threads
    for (nlohmann::json* c : {&ca, &cb}) {
        (*c)["render"].erase("output");
        (*c)["render"].erase("threads");
    }
    EXPECT_EQ(cb, ca) << "the replay's record renders the same run again";

    const vpm::Image ia = vpm::read_exr(dir.path / "a.exr"), ib = vpm::read_exr(dir.path / "b.exr");
    ASSERT_EQ(ia.rgb.size(), ib.rgb.size());
    size_t differing = 0;
    for (size_t i = 0; i < ia.rgb.size(); ++i) differing += ia.rgb[i] != ib.rgb[i];
    EXPECT_EQ(differing, 0u) << "of " << ia.rgb.size() << " values";
    EXPECT_GT(ia.mean(), 0.0);
}

}  // namespace

// The photon map's plan sizes photons and samples per pass from counts; the pass count is the clock's.
TEST(ReplayCli, TimeLimitedPhotonMapRunRendersAgainBitForBitFromItsRecord) {
    expect_replay_is_bit_for_bit(fog_scene("photon_map", 0.8));
}

// The path tracer's passes of 1 spp go in groups whose sizes follow the clock; the image, the count.
TEST(ReplayCli, TimeLimitedPathTracerRunRendersAgainBitForBitFromItsRecord) {
    expect_replay_is_bit_for_bit(fog_scene("path", 0.1));
}

// The auto integrator's pilot chooses the path tracer or the photon map, again in the replay.
TEST(ReplayCli, TimeLimitedAutoRunRendersAgainBitForBitFromItsRecord) {
    expect_replay_is_bit_for_bit(fog_scene("auto", 0.6));
}

// The count is a time limit's: without one it is refused (render.passes fixes a count), as is one
// below render.passes, which a time-limited run always renders.
TEST(ReplayCli, TimeLimitPassesNeedsATimeLimitAndAtLeastThePasses) {
    ScratchDir dir;
    write_file(dir.path / "scene.toml", tiny_scene("time_limit_passes = 3\n"));
    Outcome o = run_vpm("render " + quote(dir.path / "scene.toml") + " -o " + quote(dir.path / "a.exr"), dir.path);
    EXPECT_EQ(o.code, 1);
    EXPECT_NE(o.err.find("render.time_limit_passes: is the pass count a render.time_limit took; it needs render.time_limit > 0"),
              std::string::npos) << o.err;
    EXPECT_FALSE(fs::exists(dir.path / "a.exr"));
    write_file(dir.path / "scene.toml", fog_scene("path", 1.0));
    o = run_vpm("render " + quote(dir.path / "scene.toml") + " --set render.passes=4 --set render.time_limit_passes=3 -o " +
                    quote(dir.path / "a.exr"),
                dir.path);
    EXPECT_EQ(o.code, 1);
    EXPECT_NE(o.err.find("render.time_limit_passes: 3 is fewer than render.passes = 4"), std::string::npos) << o.err;
}
