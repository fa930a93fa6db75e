// Negative radiance is counted, never hidden (render/run/render_loop.h, run_outputs.h): a sample
// with a channel below zero is kept in the mean and counted in render.negative_samples, an image's
// negative pixels in render.negative_pixels. The photon map's linear extinction at g = -0.999 (a
// few photons carry each sum, photon/estimate/linear_estimate.h) falls back where its corrected sum
// would go negative, so the image has no negative sample and the run counts the fallbacks.
#include <gtest/gtest.h>

#include "render/integrator.h"
#include "render/run/render_loop.h"
#include "render/run/run.h"
#include "render/run/run_config.h"
#include "render/run/run_outputs.h"
#include "render/photon_map/photon_map_stats.h"

using namespace vpm;

namespace {

// -1 in red for rays leaving to the right of the camera's axis, 1 elsewhere.
class SignedIntegrator final : public Integrator {
public:
    explicit SignedIntegrator(const Vec3& right) : right_(right) {}
    Rgb radiance(const Ray& ray, Rng&) const override {
        return ray.dir.dot(right_) > 0.0 ? Rgb(-1.0, 1.0, 1.0) : Rgb::Ones();
    }
    std::string name() const override { return "signed"; }

private:
    Vec3 right_;
};

}  // namespace

TEST(NegativeRadiance, NegativeSamplesAreCountedAndKeptInTheMean) {
    const Camera camera(Vec3(0, 0, 5), Vec3::Zero(), Vec3::UnitY(), 40.0, 8, 4);
    const SignedIntegrator integrator(Vec3::UnitX());
    RenderOptions o;
    o.width = 8;
    o.height = 4;
    o.spp = 2;
    o.progress = false;
    RenderStats stats;
    const Image image = render_image(camera, integrator, o, stats);
    EXPECT_EQ(stats.nonfinite_samples, 0u);
    // The right half of the image: 4 columns x 4 rows x 2 samples (the camera's x pixel grows to +x).
    EXPECT_EQ(stats.negative_samples, 32u);
    EXPECT_EQ(count_negative_pixels(image), 16u);
    EXPECT_EQ(count_nonfinite_pixels(image), 0u);
    EXPECT_FLOAT_EQ(image.at(7, 0)[0], -1.0f);   // kept, not clamped
}

TEST(NegativeRadiance, LinearExtinctionAtStrongBackScatteringStaysNonNegativeAndCountsItsFallbacks) {
    const RunConfig config = RunConfig::load(
        VPM_SOURCE_DIR "/configs/homogeneous.toml",
        {"render.width=32", "render.height=32", "render.integrator=\"photon_map\"", "photons.count=200000",
         "render.spp=64", "photons.gather=\"collision\"", "media.0.g=-0.999"});
    RunOptions o;
    o.progress = false;
    const RunResult result = run(config, o);
    EXPECT_EQ(result.stats.render.nonfinite_samples, 0u);
    EXPECT_EQ(result.stats.render.negative_samples, 0u);   // 0.6% of the samples before the fallback
    EXPECT_EQ(count_negative_pixels(result.image), 0u);
    ASSERT_TRUE(PhotonMapStats::of(result.stats).linear_fallbacks.has_value());
    EXPECT_GT(*PhotonMapStats::of(result.stats).linear_fallbacks, 0u);
    EXPECT_GT(result.image.mean(), 0.0);
}
