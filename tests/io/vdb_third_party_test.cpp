// A VDB written by another tool (OpenVDB's Python bindings, tests/data/vdb/make_puff.py), shipped
// with the repository so that a plain clone tests the loader on a file vpm did not write.
#include <gtest/gtest.h>

#include <cmath>

#include "core/density_grid.h"
#include "io/vdb_io.h"

using namespace vpm;

namespace {

// The formula of make_puff.py; voxels below 1e-3 were left inactive (background 0).
double puff(int i, int j, int k) {
    const double r = std::sqrt(double(i * i + j * j + k * k));
    const double d = std::pow(std::max(0.0, 1.0 - r / 10.0), 2) * (1.0 + 0.25 * std::sin(i / 2.0));
    return d >= 1e-3 ? d : 0.0;
}

const std::string kPuff = VPM_TEST_DATA_DIR "/vdb/puff.vdb";

}  // namespace

TEST(VdbThirdParty, PuffWrittenByPyopenvdbLoads) {
    const DensityGrid g = load_vdb_density(kPuff, "density");
    EXPECT_EQ(g.name(), "density");
    int64_t active = 0;
    for (int i = -12; i < 12; ++i)
        for (int j = -12; j < 12; ++j)
            for (int k = -12; k < 12; ++k) {
                ASSERT_NEAR(g.voxel(i, j, k), puff(i, j, k), 1e-6) << i << " " << j << " " << k;
                active += puff(i, j, k) > 0.0;
            }
    EXPECT_EQ(g.active_voxel_count(), active);
    EXPECT_FLOAT_EQ(g.max_density(), 1.0f);
    // Voxel size 0.05, translated by (0.25, 1, -0.5).
    const Eigen::Affine3d& m = g.index_to_world();
    EXPECT_TRUE(m.linear().isApprox(0.05 * Eigen::Matrix3d::Identity(), 1e-12));
    EXPECT_TRUE(m.translation().isApprox(Eigen::Vector3d(0.25, 1.0, -0.5), 1e-12));
}

TEST(VdbThirdParty, PuffFoundWithoutAGridName) {
    EXPECT_EQ(load_vdb_density(kPuff, "").name(), "density");
}
