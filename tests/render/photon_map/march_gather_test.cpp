// The march (photons.gather = "march") in a heterogeneous medium, issue 20 item 4: points from the
// medium's exact extinction (transport/march_points.h) weigh albedo P / n times the other media's
// transmittance, so the reported relative weights are at most 1 where block-majorant points
// reached 8e4 (the matrix's blob at optical thickness 1000); the march agrees with the path
// tracer; a seed gives the same image on 1 and 2 threads.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "render/run/run.h"
#include "support/io_test_util.h"
#include "support/render_statistics.h"
#include "render/photon_map/photon_map_stats.h"

using namespace vpm;

namespace {

class MarchGather : public vpm_test::TempDirTest {
protected:
    // The scene matrix's blob cell (analysis/matrix/scene_matrix.cpp) at peak extinction about
    // 0.75 sigma_t_scale, optionally with a homogeneous sphere overlapping it.
    std::string blob(double sigma_t_scale, bool sphere = false) {
        const auto p = dir_ / "blob.toml";
        std::ofstream f(p);
        f << "[render]\nwidth = 12\nheight = 12\nspp = 4\n\n[camera]\nposition = [0.0, 0.0, 4.0]\nlook_at = [0.0, 0.0, 0.0]\n"
             "fov = 40.0\n\n[photons]\ncount = 20000\n\n[[lights]]\ntype = \"point\"\nposition = [2.0, 2.0, 2.0]\nintensity = 20.0\n\n"
             "[[media]]\ntype = \"grid\"\nfile = \"" VPM_SOURCE_DIR "/media/blob.vdb\"\n"
             "transform = { scale = 1.3333333333333333 }\nsigma_t_scale = "
          << sigma_t_scale << "\nalbedo = 0.9\ng = 0.0\n";
        if (sphere)
            f << "\n[[media]]\ntype = \"homogeneous\"\nshape = \"sphere\"\ncenter = [0.3, 0.0, 0.0]\nradius = 0.6\n"
                 "sigma_t_scale = 2.0\nalbedo = 0.8\n";
        return p.string();
    }
    static RunResult render(const std::string& config, std::vector<std::string> sets) {
        sets.push_back("render.integrator=\"photon_map\"");
        RunOptions o;
        o.progress = false;
        return run(RunConfig::load(config, sets), o);
    }
};

}  // namespace

TEST_F(MarchGather, WeightsStayBoundedInADenseSmoothGrid) {
    // sigma_t_scale 1500: optical thickness ~1000 across the blob, where block-majorant points
    // weighed up to 8e4 (mean 6). One medium: every point weighs exactly albedo P / n.
    const RunResult r = render(blob(1500.0), {"photons.gather=\"march\"", "render.spp=1", "render.width=8", "render.height=8"});
    ASSERT_TRUE(PhotonMapStats::of(r.stats).march_weight_max.has_value());
    EXPECT_EQ(*PhotonMapStats::of(r.stats).march_weight_max, 1.0);
    EXPECT_EQ(*PhotonMapStats::of(r.stats).march_weight_mean, 1.0);
    // Two media: the other medium's transmittance multiplies the weight, so at most 1, and below 1
    // on average where the sphere shades the blob.
    const RunResult two = render(blob(8.0, true), {"photons.gather=\"march\"", "render.spp=1", "render.width=8", "render.height=8"});
    ASSERT_TRUE(PhotonMapStats::of(two.stats).march_weight_max.has_value());
    EXPECT_LE(*PhotonMapStats::of(two.stats).march_weight_max, 1.0);
    EXPECT_LT(*PhotonMapStats::of(two.stats).march_weight_mean, 0.95);
    EXPECT_GT(*PhotonMapStats::of(two.stats).march_weight_mean, 0.0);
}

TEST_F(MarchGather, AgreesWithThePathTracerInAGrid) {
    // Optical thickness ~5 across the blob, overlapped by a homogeneous sphere (both estimators'
    // mean image over independent runs), within three combined standard errors (the blob is smooth:
    // 64 maps read -0.06% +- 0.71% against the path tracer).
    const std::string config = blob(8.0, true);
    test::Sample path, march;
    for (int r = 0; r < 6; ++r) {
        RunOptions o;
        o.progress = false;
        o.stream_offset = uint64_t(r);
        path.add(run(RunConfig::load(config, {"render.spp=16"}), o).image.mean());
        march.add(run(RunConfig::load(config, {"render.integrator=\"photon_map\"", "photons.gather=\"march\""}), o).image.mean());
    }
    ASSERT_GT(path.mean(), 0.0);
    std::printf("path tracer %.6f +- %.6f, march %.6f +- %.6f\n", path.mean(), path.se(), march.mean(), march.se());
    const double se = std::hypot(path.se(), march.se());
    EXPECT_NEAR(march.mean(), path.mean(), 3.0 * se);
}

TEST_F(MarchGather, SameImageOnOneAndTwoThreads) {
    const std::string config = blob(8.0, true);
    const RunResult one = render(config, {"photons.gather=\"march\"", "render.threads=1"});
    const RunResult two = render(config, {"photons.gather=\"march\"", "render.threads=2"});
    ASSERT_EQ(one.image.rgb.size(), two.image.rgb.size());
    EXPECT_TRUE(one.image.rgb == two.image.rgb);
    EXPECT_GT(one.image.mean(), 0.0);
}

TEST_F(MarchGather, MassCountQueriesThinSegmentsOnce) {
    // photons.march_points = "mass" (the default) gives a crossed medium ceil(4 (1 - T)) points
    // instead of 4 (transport/march_count.h): in the thin blob (optical thickness ~1 across)
    // nearly every segment holds under a quarter of the mass, so the kNN queries fall towards a
    // quarter of "fixed"'s; where 4 (1 - T) > 1 some segments keep 2..4, so the ratio stays above 1/4.
    const std::vector<std::string> sets = {"photons.gather=\"march\"", "render.spp=2", "render.width=8", "render.height=8"};
    auto with = [&](const std::string& rule) {
        auto s = sets;
        s.push_back("photons.march_points=\"" + rule + "\"");
        return render(blob(1.5), s);
    };
    const RunResult fixed = with("fixed"), mass = with("mass");
    ASSERT_TRUE(PhotonMapStats::of(fixed.stats).volume_estimates && PhotonMapStats::of(mass.stats).volume_estimates);
    const double f = double(PhotonMapStats::of(fixed.stats).volume_estimates->queries), m = double(PhotonMapStats::of(mass.stats).volume_estimates->queries);
    ASSERT_GT(f, 0.0);
    std::printf("queries: fixed %.0f, mass %.0f\n", f, m);
    EXPECT_LT(m, 0.5 * f);
    EXPECT_GE(m, 0.25 * f);
    EXPECT_TRUE(mass.image.rgb != fixed.image.rgb);   // the rule is read: other points, another image
}
