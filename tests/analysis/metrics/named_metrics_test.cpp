// The named error metrics (lib/analysis/metrics/error_metrics.h: relMSE, relRMSE, SMAPE), their pixel masks
// (pixel_mask.h) and the reference's noise floor (reference_noise.h): hand-computed values on tiny
// images, and the floor's subtraction checked statistically on synthetic noise.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "analysis/metrics/error_metrics.h"
#include "analysis/metrics/pixel_mask.h"
#include "analysis/metrics/reference_noise.h"
#include "core/error.h"
#include "core/sampling/rng.h"

namespace vpm {
namespace {

// Grey pixels: luminance = value (the Rec. 709 weights sum to 1).
Image grey(std::vector<float> v, int width = 0) {
    const int w = width > 0 ? width : int(v.size());
    Image im(w, int(v.size()) / w);
    for (size_t i = 0; i < v.size(); ++i) im.set(int(i) % w, int(i) / w, Rgb(v[i], v[i], v[i]));
    return im;
}

MetricOptions options(ErrorMetric m, const PixelMask* mask = nullptr) {
    MetricOptions o;
    o.metric = m;
    o.mask = mask;
    return o;
}

TEST(NamedMetrics, HandComputedWithoutNoise) {
    const Image ref = grey({1, 3, 0});
    const Image img = grey({2, 3, 0.1f});   // differences 1, 0, 0.1
    const MetricValue mse = measure_error(img, ref, options(ErrorMetric::rel_mse));
    EXPECT_NEAR(mse.value, (1.0 / 1.01 + 0.0 + 0.01 / 0.01) / 3.0, 1e-6);
    EXPECT_EQ(mse.value, mse.raw);
    EXPECT_TRUE(std::isnan(mse.floor));
    EXPECT_EQ(mse.pixels, 3u);
    const MetricValue rmse = measure_error(img, ref, options(ErrorMetric::rel_rmse));
    EXPECT_NEAR(rmse.value, std::sqrt((1.0 + 0.01) / 3.0) / (4.0 / 3.0), 1e-6);
    const MetricValue smape = measure_error(img, ref, options(ErrorMetric::smape));
    EXPECT_NEAR(smape.value, (1.0 / 3.01 + 0.0 + 0.1 / 0.11) / 3.0, 1e-6);
    // The default is relMSE with eps 0.01.
    EXPECT_EQ(MetricOptions().metric, ErrorMetric::rel_mse);
    EXPECT_EQ(MetricOptions().epsilon, 0.01);
}

// A glint: one bright pixel badly off decides the linear metric, not the per-pixel relative one.
TEST(NamedMetrics, AGlintDecidesRelRmseButNotRelMse) {
    std::vector<float> r(100, 1.0f), i(100, 1.05f);
    r[0] = 1000.0f;
    i[0] = 500.0f;
    const Image ref = grey(r), img = grey(i);
    const double rmse = measure_error(img, ref, options(ErrorMetric::rel_rmse)).value;
    const double mse = measure_error(img, ref, options(ErrorMetric::rel_mse)).value;
    EXPECT_GT(rmse, 4.0);               // 500 / sqrt(100) / 11 = 4.5
    EXPECT_LT(mse, 0.25 / 100 + 0.01);  // the glint weighs (0.5)^2, each other pixel 0.0025 / 1.01
    PixelMask mask(100, 1);
    mask.exclude({0, 0, 1, 1});
    const MetricValue masked = measure_error(img, ref, options(ErrorMetric::rel_rmse, &mask));
    EXPECT_NEAR(masked.value, 0.05, 1e-6);
    EXPECT_EQ(masked.pixels, 99u);
    EXPECT_EQ(masked.masked_out, 1u);
}

TEST(NamedMetrics, FloorIsSubtractedInTheMetricsUnits) {
    const Image ref = grey({1, 3});
    const Image img = grey({2, 3});
    const Image var = grey({0.04f, 0.36f});
    const MetricValue mse = measure_error(img, ref, options(ErrorMetric::rel_mse), &var);
    EXPECT_NEAR(mse.floor, (0.04 / 1.01 + 0.36 / 9.01) / 2.0, 1e-7);
    EXPECT_NEAR(mse.value, mse.raw - mse.floor, 1e-12);
    const MetricValue rmse = measure_error(img, ref, options(ErrorMetric::rel_rmse), &var);
    EXPECT_NEAR(rmse.floor, std::sqrt(0.2) / 2.0, 1e-7);
    EXPECT_NEAR(rmse.value, std::sqrt(0.5 - 0.2) / 2.0, 1e-7);
    // An image as close as the reference's own noise: the value goes negative rather than being clamped.
    const Image var_big = grey({4, 4});
    EXPECT_LT(measure_error(img, ref, options(ErrorMetric::rel_rmse), &var_big).value, 0.0);
    EXPECT_TRUE(std::isnan(measure_error(img, ref, options(ErrorMetric::smape), &var).floor));
}

TEST(NamedMetrics, NamesAndBadInput) {
    EXPECT_EQ(parse_error_metric("relMSE"), ErrorMetric::rel_mse);
    EXPECT_EQ(parse_error_metric("rel_rmse"), ErrorMetric::rel_rmse);
    EXPECT_EQ(parse_error_metric("SMAPE"), ErrorMetric::smape);
    try {
        parse_error_metric("psnr");
        FAIL();
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("allowed: relmse, relrmse, smape"), std::string::npos) << e.what();
    }
    EXPECT_EQ(metric_name(ErrorMetric::rel_mse), "relMSE");
    EXPECT_NE(metric_formula(ErrorMetric::rel_mse, 0.01).find("(R^2 + 0.01)"), std::string::npos);
    EXPECT_THROW(measure_error(grey({1, 2}), grey({1}), MetricOptions()), Error);
    PixelMask none(2, 1);
    none.exclude({0, 0, 2, 1});
    EXPECT_THROW(measure_error(grey({1, 2}), grey({1, 2}), options(ErrorMetric::rel_mse, &none)), Error);
    MetricOptions zero_eps;
    zero_eps.epsilon = 0;
    EXPECT_THROW(measure_error(grey({1, 2}), grey({1, 2}), zero_eps), Error);
    // A non-finite image pixel is left out and counted; a non-finite reference pixel is refused.
    const MetricValue v = measure_error(grey({1, NAN}), grey({1, 2}), MetricOptions());
    EXPECT_EQ(v.nonfinite_pixels, 1u);
    EXPECT_EQ(v.pixels, 1u);
    EXPECT_THROW(measure_error(grey({1, 2}), grey({1, INFINITY}), MetricOptions()), Error);
}

TEST(PixelMask, CropExcludeAndImage) {
    PixelMask m(4, 3);
    EXPECT_EQ(m.compared_count(), 12u);
    EXPECT_EQ(m.describe(), "all 12 pixels");
    m.crop(parse_pixel_rect("1,0,4,2", "--crop"));     // 3 x 2
    EXPECT_EQ(m.compared_count(), 6u);
    m.exclude(parse_pixel_rect("3,1,9,9", "--exclude"));   // clipped: drops (3, 1)
    EXPECT_EQ(m.compared_count(), 5u);
    EXPECT_FALSE(m.compared(0));
    EXPECT_TRUE(m.compared(1));
    EXPECT_FALSE(m.compared(7));
    Image mask(4, 3);
    mask.set(1, 0, Rgb(1, 1, 1));
    mask.set(2, 1, Rgb(0, 0.5, 0));
    m.intersect(mask, "mask.exr");
    EXPECT_EQ(m.compared_count(), 2u);
    EXPECT_EQ(m.describe(), "2 of 12 pixels (crop 1,0,4,2, exclude 3,1,9,9, mask mask.exr)");
    EXPECT_THROW(m.intersect(Image(3, 3), "small.exr"), Error);
    EXPECT_THROW(parse_pixel_rect("1,2,3", "--crop"), Error);
    EXPECT_THROW(parse_pixel_rect("3,0,1,2", "--crop"), Error);
    EXPECT_THROW(parse_pixel_rect("0,0,1,1x", "--crop"), Error);
    PixelMask outside(4, 3);
    EXPECT_THROW(outside.crop({10, 10, 12, 12}), Error);
}

TEST(ReferenceNoise, HalvesGiveTheirMeanAndTheVarianceOfIt) {
    const NoisyReference r = reference_from_halves(grey({1, 2}), grey({3, 2}), "a + b");
    EXPECT_NEAR(r.image.rgb[0], 2.0f, 1e-6);
    EXPECT_NEAR(r.image.rgb[3], 2.0f, 1e-6);
    ASSERT_TRUE(r.variance);
    EXPECT_NEAR(r.variance->rgb[0], 1.0f, 1e-6);   // ((1 - 3) / 2)^2
    EXPECT_NEAR(r.variance->rgb[3], 0.0f, 1e-6);
    EXPECT_THROW(reference_from_halves(grey({1, 2}), grey({1}), "x"), Error);
    EXPECT_EQ(variance_path_for("out/ref.exr"), std::filesystem::path("out/ref.variance.exr"));
}

// The floor makes the error against a noisy reference an unbiased estimate of the error against
// the truth: an image with noise s_i against a reference made of two halves with noise s_h each.
// In MSE units (relRMSE^2 L^2) the expectation is s_i^2; per-pixel terms are independent, so the
// standard error is their sample standard deviation / sqrt(P).
TEST(ReferenceNoise, SubtractingTheFloorRecoversTheImagesOwnError) {
    const int P = 40000;
    const double truth = 2.0, s_i = 0.1, s_h = 0.3;   // the reference's noise (0.3 / sqrt 2) swamps the image's
    Rng rng(7, 0);
    auto gauss = [&] {
        const double u1 = std::max(rng.uniform(), 1e-300), u2 = rng.uniform();
        return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * kPi * u2);
    };
    std::vector<float> img(P), a(P), b(P);
    for (int p = 0; p < P; ++p) {
        img[size_t(p)] = float(truth + s_i * gauss());
        a[size_t(p)] = float(truth + s_h * gauss());
        b[size_t(p)] = float(truth + s_h * gauss());
    }
    const NoisyReference ref = reference_from_halves(grey(a, 200), grey(b, 200), "halves");
    const Image image = grey(img, 200);
    const MetricValue m = measure_error(image, ref.image, options(ErrorMetric::rel_rmse), &*ref.variance);
    double L = 0;
    for (int p = 0; p < P; ++p) L += ref.image.rgb[3 * size_t(p)] / double(P);
    std::vector<double> term(P);
    double mean = 0;
    for (int p = 0; p < P; ++p) {
        const double d = img[size_t(p)] - ref.image.rgb[3 * size_t(p)];
        term[size_t(p)] = d * d - ref.variance->rgb[3 * size_t(p)];
        mean += term[size_t(p)] / P;
    }
    double var = 0;
    for (double t : term) var += (t - mean) * (t - mean) / (P - 1);
    const double se = std::sqrt(var / P);
    const double estimate = m.value * std::abs(m.value) * L * L;   // back to MSE units
    EXPECT_NEAR(estimate, mean, 1e-6 * s_i * s_i);                 // the metric computes exactly this
    EXPECT_NEAR(estimate, s_i * s_i, 3.0 * se) << "se " << se;
    // Without the floor the error is the reference's: raw^2 L^2 ~ s_i^2 + s_h^2 / 2.
    EXPECT_GT(m.raw * m.raw * L * L, 3.0 * s_i * s_i);
}

}  // namespace
}  // namespace vpm
