// render/plan/work_units.h: the price of a kNN query grows with the stored photons (log2: the kd-tree's
// depth), is the fitted price at the reference size, and stays positive down to a single photon.
#include <gtest/gtest.h>

#include <cmath>

#include "render/plan/work_units.h"
#include "support/scene_from_config.h"

using namespace vpm;

TEST(WorkUnits, QueryPriceGrowsWithTheMapsSize) {
    const auto scene = test::scene_from_config(
        "[camera]\nposition = [0, 0, 4]\nlook_at = [0, 0, 0]\n[[lights]]\ntype = 'point'\nposition = [0, 3, 0]\nintensity = 1\n"
        "[[media]]\ntype = 'homogeneous'\nshape = 'sphere'\ncenter = [0, 0, 0]\nradius = 1\nsigma_t_scale = 1\n",
        8, 8, "work_units.toml");
    for (const int k : {8, 32, 128}) {
        const WorkUnits w = work_units(*scene, k);
        EXPECT_GT(w.query_doubling, 0.0);
        EXPECT_DOUBLE_EQ(query_price(w, kQueryReferenceStored), w.query);
        double last = 0.0;
        for (double stored = 1.0; stored <= 1e7; stored *= 10.0) {
            const double p = query_price(w, stored);
            EXPECT_GT(p, last) << "k " << k << ", " << stored << " stored";
            EXPECT_GT(p, w.query_wide);   // a used query always costs more than a radius-bounded one
            last = p;
        }
        // Linear in log2 of the size: a doubling adds query_doubling anywhere.
        EXPECT_NEAR(query_price(w, 2e6) - query_price(w, 1e6), w.query_doubling, 1e-9 * w.query);
        // The larger k, the dearer the query at any size.
        if (k > 8) {
            EXPECT_GT(query_price(w, 1e3), query_price(work_units(*scene, 8), 1e3));
        }
    }
}
