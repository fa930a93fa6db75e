// Sweep error metrics (lib/analysis/metrics/error_metrics.h) on tiny images with hand-computed values.
// Grey pixels: luminance = value (the Rec.709 weights sum to 1).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "analysis/metrics/error_metrics.h"
#include "core/error.h"
#include "core/sampling/rng.h"

namespace vpm {
namespace {

Image grey(std::vector<float> v) {
    Image im(int(v.size()), 1);
    for (size_t i = 0; i < v.size(); ++i) im.set(int(i), 0, Rgb(v[i], v[i], v[i]));
    return im;
}

TEST(ErrorMetrics, LuminanceWeightsSumToOne) { EXPECT_NEAR(luminance(1, 1, 1), 1.0, 1e-12); }

TEST(ErrorMetrics, RunErrorHandComputed) {
    const Image ref = grey({1, 3});    // mean luminance L = 2
    const Image img = grey({2, 3});    // differences (1, 0)
    const RunError e = run_error(img, ref);
    EXPECT_NEAR(e.rel_rmse, std::sqrt(0.5) / 2.0, 1e-7);
    EXPECT_NEAR(e.rel_mean_error, 0.25, 1e-7);
    EXPECT_EQ(e.pixels, 2u);
    EXPECT_EQ(e.nonfinite_pixels, 0u);
}

TEST(ErrorMetrics, RepeatErrorBiasVarianceSplitHandComputed) {
    const Image ref = grey({1, 3});    // L = 2, L^2 = 4
    const Image a = grey({2, 3});      // d = (1, 0)
    const Image b = grey({0, 5});      // d = (-1, 2)
    const RepeatError e = repeat_error({&a, &b}, ref);
    // pixel 0: mean 0, s2 = 2; pixel 1: mean 1, s2 = 2
    EXPECT_NEAR(e.rel_mse, (1 + 0 + 1 + 4) / 4.0 / 4.0, 1e-7);             // 0.375
    EXPECT_NEAR(e.rel_variance, 2.0 / 4.0, 1e-7);                          // 0.5
    EXPECT_NEAR(e.rel_bias2, ((0 - 1.0) + (1 - 1.0)) / 2.0 / 4.0, 1e-7);    // -0.125
    EXPECT_NEAR(e.rel_bias2 + e.rel_variance, e.rel_mse, 1e-12);
    EXPECT_NEAR(e.rel_rmse, std::sqrt(0.375), 1e-7);
    EXPECT_NEAR(e.rel_std, std::sqrt(0.5), 1e-7);
    EXPECT_NEAR(e.rel_bias, 0.25, 1e-7);      // both repeats: mean difference 0.5 / L
    EXPECT_NEAR(e.rel_bias_se, 0.0, 1e-7);
    EXPECT_EQ(e.repeats, 2u);
}

TEST(ErrorMetrics, RepeatBiasStandardErrorHandComputed) {
    const Image ref = grey({1, 3});
    const Image a = grey({2, 3}), b = grey({1, 3}), c = grey({3, 5});   // per-repeat rel. bias 0.25, 0, 1
    const RepeatError e = repeat_error({&a, &b, &c}, ref);
    EXPECT_NEAR(e.rel_bias, 1.25 / 3.0, 1e-7);
    // sample variance of (0.25, 0, 1) = 0.541667 / 2; se = sqrt(var / 3)
    EXPECT_NEAR(e.rel_bias_se, std::sqrt(0.5416666667 / 2.0 / 3.0), 1e-7);
}

TEST(ErrorMetrics, DecompositionIsExactOnRandomImages) {
    Rng rng(5, 0);
    Image ref(7, 5);
    for (auto& v : ref.rgb) v = float(0.5 + rng.uniform());
    std::vector<Image> reps(4, Image(7, 5));
    for (auto& im : reps)
        for (size_t i = 0; i < im.rgb.size(); ++i) im.rgb[i] = float(ref.rgb[i] * (1.1 + 0.4 * (rng.uniform() - 0.5)));
    std::vector<const Image*> ptrs;
    for (auto& im : reps) ptrs.push_back(&im);
    const RepeatError e = repeat_error(ptrs, ref);
    EXPECT_NEAR(e.rel_bias2 + e.rel_variance, e.rel_mse, 1e-12 * e.rel_mse);
    // mean of the per-run squared RMSEs is the MSE
    double m = 0;
    for (auto& im : reps) m += std::pow(run_error(im, ref).rel_rmse, 2) / 4.0;
    EXPECT_NEAR(m, e.rel_mse, 1e-9 * e.rel_mse);
    EXPECT_GT(e.rel_bias, 0.05);   // images are ~10% too bright
}

TEST(ErrorMetrics, NonFinitePixelsAreCountedAndLeftOut) {
    const Image ref = grey({1, 3});
    Image img = grey({2, 3});
    img.set(1, 0, Rgb(std::numeric_limits<double>::quiet_NaN(), 1, 1));
    const RunError e = run_error(img, ref);
    EXPECT_EQ(e.nonfinite_pixels, 1u);
    EXPECT_EQ(e.pixels, 1u);
    EXPECT_NEAR(e.rel_rmse, 1.0 / 2.0, 1e-7);   // only pixel 0, still relative to the full L
    const Image ok = grey({1, 3});
    const RepeatError r = repeat_error({&img, &ok}, ref);
    EXPECT_EQ(r.nonfinite_pixels, 1u);
    EXPECT_EQ(r.pixels, 1u);
}

TEST(ErrorMetrics, RejectsBadReferenceAndSizes) {
    EXPECT_THROW(reference_scale(grey({0, 0})), Error);
    EXPECT_THROW(run_error(grey({1, 2, 3}), grey({1, 3})), Error);
    const Image one = grey({2, 3});
    const RepeatError r = repeat_error({&one}, grey({1, 3}));
    EXPECT_TRUE(std::isnan(r.rel_variance));   // one repeat: no variance estimate
    EXPECT_NEAR(r.rel_mse, 0.125, 1e-7);
}

}  // namespace
}  // namespace vpm
