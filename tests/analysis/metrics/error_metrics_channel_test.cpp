#include <gtest/gtest.h>

#include "analysis/metrics/error_metrics.h"
#include "core/error.h"

using namespace vpm;

TEST(ImageCompare, KnownErrors) {
    Image ref(2, 1), img(2, 1);
    ref.set(0, 0, Rgb(1, 1, 1));
    ref.set(1, 0, Rgb(3, 3, 3));
    img.set(0, 0, Rgb(2, 2, 2));   // +1
    img.set(1, 0, Rgb(3, 3, 3));   //  0
    const ImageError e = compare_images(img, ref);
    EXPECT_DOUBLE_EQ(e.rmse, std::sqrt(0.5));
    EXPECT_DOUBLE_EQ(e.reference_mean, 2.0);
    EXPECT_DOUBLE_EQ(e.relative_rmse, std::sqrt(0.5) / 2.0);
    EXPECT_DOUBLE_EQ(e.relative_bias, 2.5 / 2.0 - 1.0);
    EXPECT_EQ(e.nonfinite, 0u);
}

TEST(ImageCompare, SizeMismatchThrowsAndNonFiniteIsCounted) {
    EXPECT_THROW(compare_images(Image(2, 2), Image(2, 1)), Error);
    Image ref(1, 1), img(1, 1);
    ref.set(0, 0, Rgb(1, 1, 1));
    img.set(0, 0, Rgb(std::nan(""), 1, 1));
    const ImageError e = compare_images(img, ref);
    EXPECT_EQ(e.nonfinite, 1u);
    EXPECT_DOUBLE_EQ(e.rmse, 0.0);
}
