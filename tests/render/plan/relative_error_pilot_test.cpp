// The auto pilot ranks candidates by the relative error the renderer is judged by (render/plan/
// relative_error.h: relMSE, each pixel's error over R^2 + 0.01), not by a linear per-sample variance.
// Synthetic: half the image is a bright lamp seen through glass (luminance 100), half a dim room
// (0.3). Candidate "bright_noise" is noisy on the lamp only, "dim_noise" on the room only, at equal
// cost. Linear, the lamp's noise is 3,300x the room's in variance; relative, the room's is 30x the lamp's.
// (glass_bulb_smoke chose the path tracer on the linear figure at 318x the photon map's relMSE:
// docs/studies/caustic_scenes.md.)
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <vector>

#include "core/sampling/rng.h"
#include "photon/map/photon_map.h"
#include "render/plan/map_noise_pilot.h"
#include "render/plan/pass_plan.h"
#include "render/plan/relative_error.h"
#include "scene/camera.h"

using namespace vpm;

namespace {

constexpr int kSide = 32;
constexpr double kLamp = 100.0, kRoom = 0.3;
constexpr double kLampSpread = 17.320508075688775;   // uniform on +-sqrt(300): variance 100
constexpr double kRoomSpread = 0.3;   // uniform on +-0.3: variance 0.03

Camera test_camera() { return Camera(Vec3(0, 0, 4), Vec3(0, 0, 0), Vec3(0, 1, 0), 40.0, kSide, kSide); }

// Both candidates measured by one pilot: candidate 0's noise on the lamp's half, candidate 1's on the room's.
std::vector<GatherMeasurement> measure(const Camera& camera) {
    int candidate = 0;
    std::atomic<int> traces{0};
    MapNoisePilotHooks hooks;
    hooks.use = [&](int c, const PhotonMap*) { candidate = c; };
    hooks.trace = [&](const Ray& r, Rng& rng) {
        ++traces;
        const bool lamp = r.dir.x() < 0.0;   // the left half of the image (either way round: it is half)
        const double u = 2.0 * rng.uniform() - 1.0;
        const bool noisy = (candidate == 0) == lamp;
        const double mean = lamp ? kLamp : kRoom;
        return Rgb::Constant(mean + (noisy ? u * (lamp ? kLampSpread : kRoomSpread) : 0.0));
    };
    hooks.counts = [&] {   // one work unit per sample; no map estimate used, so no halves are traced
        CountedOperations c;
        c.rays = double(traces.load());
        return c;
    };
    hooks.work = [](const CountedOperations& c) { return c.rays; };
    const PhotonMap map;
    return measure_gathers(camera, map, {{"bright_noise", true}, {"dim_noise", true}}, hooks, 7, 0);
}

}  // namespace

TEST(RelativeErrorPilot, RanksCandidatesByRelativeNotLinearVariance) {
    const auto m = measure(test_camera());
    ASSERT_EQ(m.size(), 2u);
    // Half the pixels of each grid carry the noise: relative, variance 100 / (100^2 + 0.01) on the lamp
    // and 0.03 / (0.3^2 + 0.01) on the room, halved. The weights come from the pixels' means over both
    // candidates' samples (8 or 2 per pixel each), so they are read within the means' noise: 10% here.
    const double lamp = 0.5 * 100.0 / (kLamp * kLamp + kRelativeErrorEpsilon);
    const double room = 0.5 * 0.03 / (kRoom * kRoom + kRelativeErrorEpsilon);
    EXPECT_NEAR(m[0].v_camera, lamp, 0.35 * lamp);   // 16 two-sample and 32 eight-sample variances: SE ~ 15%
    EXPECT_NEAR(m[1].v_camera, room, 0.35 * room);
    // Linear the lamp's candidate is 3,300x the noisier; relative the room's is 30x.
    EXPECT_GT(m[1].v_camera, 10.0 * m[0].v_camera);
    EXPECT_EQ(m[0].sample_cost, m[1].sample_cost);
    // The plan, at equal cost and no map noise, takes the one with the lower relative error.
    PlanInputs in;
    in.candidates = m;
    in.pixels = double(kSide * kSide);
    in.count = 1000;
    in.spp = 4;
    const PassPlan plan = plan_passes(in);
    EXPECT_EQ(m[size_t(plan.chosen)].name, "bright_noise");
    EXPECT_LT(plan.score[0], plan.score[1]);
}
