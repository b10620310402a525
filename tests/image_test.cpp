#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>

#include "core/image.h"

namespace glarelab {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

TEST(Image, ConstructorSizesAndFills) {
  const ImageRGBA image(5, 3, 0.25f);
  EXPECT_EQ(image.width_px, 5);
  EXPECT_EQ(image.height_px, 3);
  ASSERT_EQ(image.rgba.size(), 4u * 5u * 3u);
  EXPECT_TRUE(image.depth.empty());
  EXPECT_FALSE(image.empty());
  for (std::size_t i = 0; i < image.rgba.size(); i += 4) {
    EXPECT_EQ(image.rgba[i + 0], 0.25f);
    EXPECT_EQ(image.rgba[i + 1], 0.25f);
    EXPECT_EQ(image.rgba[i + 2], 0.25f);
    EXPECT_EQ(image.rgba[i + 3], 1.0f) << "new images are opaque";
  }
  // pixel(x, y) addresses row-major storage, row 0 first.
  ImageRGBA grid(4, 2);
  grid.pixel(3, 1)[1] = 7.0f;
  EXPECT_EQ(grid.rgba[4 * (1 * 4 + 3) + 1], 7.0f);
  EXPECT_TRUE(ImageRGBA(0, 4).empty());
  EXPECT_TRUE(ImageRGBA().empty());
  EXPECT_THROW(ImageRGBA(-1, 2), std::invalid_argument);
}

TEST(Image, InspectPixelsCountsEachKindPerPixel) {
  ImageRGBA image(10, 3, 1.0f);
  // 3 NaN pixels (one NaN in each colour channel position).
  image.pixel(0, 0)[0] = kNaN;
  image.pixel(1, 0)[1] = kNaN;
  image.pixel(2, 0)[2] = kNaN;
  // 1 Inf pixel with two infinite channels: still one pixel.
  image.pixel(3, 0)[0] = kInf;
  image.pixel(3, 0)[2] = kInf;
  // 12 negative pixels.
  for (int x = 0; x < 10; ++x) image.pixel(x, 1)[x % 3] = -0.5f;
  image.pixel(0, 2)[1] = -1e-30f;
  image.pixel(1, 2)[2] = -2.0f;
  // Alpha is not a luminance and is not inspected; -0 is not negative.
  image.pixel(5, 2)[3] = kNaN;
  image.pixel(6, 2)[0] = -0.0f;

  const NonFiniteReport report = inspect_pixels(image);
  EXPECT_EQ(report.nan_pixels, 3u);
  EXPECT_EQ(report.inf_pixels, 1u);
  EXPECT_EQ(report.negative_pixels, 12u);
  EXPECT_FALSE(report.clean());
  EXPECT_EQ(report.describe(), "3 NaN pixels, 1 Inf pixel, 12 negative pixels");
}

TEST(Image, NegativeInfinityIsInfAndNegative) {
  ImageRGBA image(2, 1, 0.0f);
  image.pixel(1, 0)[1] = -kInf;
  const NonFiniteReport report = inspect_pixels(image);
  EXPECT_EQ(report.nan_pixels, 0u);
  EXPECT_EQ(report.inf_pixels, 1u);
  EXPECT_EQ(report.negative_pixels, 1u);
  EXPECT_EQ(report.describe(), "1 Inf pixel, 1 negative pixel");
}

TEST(Image, CleanImageReport) {
  const NonFiniteReport report = inspect_pixels(ImageRGBA(4, 4, 100.0f));
  EXPECT_TRUE(report.clean());
  EXPECT_EQ(report.describe(), "no NaN, Inf or negative pixels");
}

TEST(Image, LuminanceUsesRec709Weights) {
  // BT.709-6 item 3.2: Y = 0.2126 R + 0.7152 G + 0.0722 B.
  EXPECT_DOUBLE_EQ(luminance_rec709(1, 0, 0), 0.2126);
  EXPECT_DOUBLE_EQ(luminance_rec709(0, 1, 0), 0.7152);
  EXPECT_DOUBLE_EQ(luminance_rec709(0, 0, 1), 0.0722);
  EXPECT_DOUBLE_EQ(luminance_rec709(1, 1, 1), 1.0);

  ImageRGBA image(2, 2, 0.0f);
  image.pixel(0, 0)[0] = 100.0f;  // Y = 21.26
  image.pixel(1, 0)[1] = 100.0f;  // Y = 71.52
  image.pixel(0, 1)[2] = 100.0f;  // Y = 7.22
  image.pixel(1, 1)[0] = 10.0f;   // Y = 10 (grey)
  image.pixel(1, 1)[1] = 10.0f;
  image.pixel(1, 1)[2] = 10.0f;
  EXPECT_NEAR(max_luminance(image), 71.52, 1e-9);
  EXPECT_NEAR(mean_luminance(image), (21.26 + 71.52 + 7.22 + 10.0) / 4.0, 1e-9);
}

TEST(Image, LuminanceSkipsNaNPixels) {
  ImageRGBA image(3, 1, 2.0f);
  image.pixel(1, 0)[0] = kNaN;
  EXPECT_NEAR(max_luminance(image), 2.0, 1e-12);
  EXPECT_NEAR(mean_luminance(image), 2.0, 1e-12);
  EXPECT_EQ(max_luminance(ImageRGBA()), 0.0);
  EXPECT_EQ(mean_luminance(ImageRGBA()), 0.0);
  // A darker-than-black (negative) image still reports its largest value.
  EXPECT_NEAR(max_luminance(ImageRGBA(2, 2, -1.0f)), -1.0, 1e-12);
}

}  // namespace
}  // namespace glarelab
