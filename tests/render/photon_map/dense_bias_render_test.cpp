// Issue 21 in the renderer: the dense albedo-0.99 sphere (configs/homogeneous.toml at sigma_t_scale
// 40), where the corrected estimate with "ball" read +1.47% at 1e6 photons and the defaults
// (photons.extinction = "linear" since the fourth session) +0.21% +- 0.11% (14 maps, docs/dense_bias.md).
// At the cheap size here (1e5 photons, 16 x 16, 6 maps) the old estimate ("ball", "ignore", set
// explicitly) reads +2.2% and the defaults +1.1% +- 0.7% (the remainder shrinks with the photon
// count: the curvature and clustering terms of docs/dense_bias.md; about 0.5% of the linear
// estimates fall back to the ball normalisation, docs/linear_fallback.md, which gives back about a
// third of the gain and makes the estimate heavier-tailed): the defaults must be within 3.5 standard
// errors of the path tracer, and on the same maps they must remove the old excess by more than 4
// standard errors of the paired difference (measured 0.00098 +- 0.00023: 4.3; 0.00106 +- 0.00005
// before the fallback). A default that went back to "ball" fails the second check.
// (The 0.5% target at 1e6 photons is measured in docs/dense_bias.md: a 1e6-photon map takes too
// long for the suite.)
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "photon/map/photon_map.h"
#include "photon/trace/photon_tracer.h"
#include "render/path/path_tracer.h"
#include "render/photon_map/photon_map_integrator.h"
#include "render/run/run_config.h"
#include "support/render_statistics.h"

using namespace vpm;

TEST(DenseBiasRender, SphereDefaultsRemoveTheOldExcess) {
    const std::vector<std::string> common = {"render.width=16", "render.height=16", "media.0.sigma_t_scale=40",
                                             "media.0.albedo=0.99", "photons.count=100000", "render.integrator=photon_map"};
    std::vector<std::string> base = common, with = common;   // the old estimate ("ball", "ignore") and the defaults
    base.insert(base.end(), {"photons.extinction=ball", "photons.clustering=ignore", "photons.store_probability=1"});
    const RunConfig before = RunConfig::load(VPM_SOURCE_DIR "/configs/homogeneous.toml", base);
    const RunConfig after = RunConfig::load(VPM_SOURCE_DIR "/configs/homogeneous.toml", with);
    const PhotonMapSettings& ps_before = photon_map_settings(before);
    const PhotonMapSettings& ps_after = photon_map_settings(after);
    const Scene& scene = *before.scene;
    test::Sample old_pm, new_pm, difference, pt;
    for (int r = 0; r < 6; ++r) {
        PhotonTraceSettings ts;
        ts.count = uint64_t(ps_after.count);
        ts.seed = 800 + uint64_t(r);
        ts.progress = false;
        ts.store_direct = ps_after.direct == DirectLighting::photon_map;   // as run_photon_pass sets it
        const PhotonMap map(trace_photons(scene, ts).photons);
        const double o = test::image_mean(before, PhotonMapIntegrator(scene, ps_before, map), 30 + uint64_t(r), 16);
        const double n = test::image_mean(after, PhotonMapIntegrator(*after.scene, ps_after, map), 30 + uint64_t(r), 16);
        old_pm.add(o);
        new_pm.add(n);
        difference.add(o - n);
    }
    for (int r = 0; r < 4; ++r) pt.add(test::image_mean(before, PathTracer(scene, ps_before.walk), 900 + uint64_t(r), 1024));
    const double se = std::sqrt(new_pm.se() * new_pm.se() + pt.se() * pt.se());
    std::printf("dense sphere, 1e5 photons: old (ball) %.5f, defaults %.5f +- %.5f, path tracer %.5f +- %.5f "
                "(defaults %+.2f%%, old %+.2f%%; paired difference %.5f +- %.5f)\n",
                old_pm.mean(), new_pm.mean(), new_pm.se(), pt.mean(), pt.se(), 100 * (new_pm.mean() / pt.mean() - 1),
                100 * (old_pm.mean() / pt.mean() - 1), difference.mean(), difference.se());
    EXPECT_LT(std::abs(new_pm.mean() - pt.mean()), 3.5 * se);
    EXPECT_GT(difference.mean(), 4.0 * difference.se());
}
