// Text screens: the rasterised text against DejaVu Sans's published metrics (units per em 2048,
// cap height 1493, x-height 1120) and the layout rules of stimuli/text_image.h.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "stimuli/text_image.h"

namespace glarelab {
namespace {

struct InkBox {
  int left = 1 << 30, top = 1 << 30, right = -1, bottom = -1;  // inclusive
  int height() const { return bottom - top + 1; }
  int width() const { return right - left + 1; }
};

// Pixels more than half covered: luminance above the midpoint of background and text.
InkBox ink_box(const ImageRGBA& image, double midpoint_cd_m2, int first_row = 0, int last_row = -1) {
  if (last_row < 0) last_row = image.height_px - 1;
  InkBox box;
  for (int y = first_row; y <= last_row; ++y)
    for (int x = 0; x < image.width_px; ++x)
      if (image.pixel(x, y)[0] > midpoint_cd_m2) {
        box.left = std::min(box.left, x);
        box.right = std::max(box.right, x);
        box.top = std::min(box.top, y);
        box.bottom = std::max(box.bottom, y);
      }
  return box;
}

TEST(TextImage, CapitalHeightMatchesTheFontsPublishedCapHeight) {
  TextImageStyle style;
  style.line_height_px = 120;  // em = 100 px
  style.text_cd_m2 = 80;
  style.background_cd_m2 = 0;
  const ImageRGBA image = render_text_image("I", style);
  ASSERT_FALSE(image.empty());
  EXPECT_EQ(image.height_px, 120);
  const InkBox box = ink_box(image, 40);
  // 1493 / 2048 em = 72.9 px; hinting snaps the outline to whole pixels.
  EXPECT_NEAR(box.height(), 100.0 * 1493.0 / 2048.0, 1.0);
  // The advance of 'I' (604 / 2048 em = 29.5 px) is the image width.
  EXPECT_NEAR(image.width_px, 100.0 * 604.0 / 2048.0, 1.0);
}

TEST(TextImage, XHeightMatchesTheFont) {
  TextImageStyle style;
  style.line_height_px = 120;
  const ImageRGBA image = render_text_image("x", style);
  const InkBox box = ink_box(image, 50);
  EXPECT_NEAR(box.height(), 100.0 * 1120.0 / 2048.0, 1.0);
}

TEST(TextImage, LuminancesStayBetweenBackgroundAndTextAndStemsReachTheTextLuminance) {
  TextImageStyle style;
  style.line_height_px = 60;
  style.text_cd_m2 = 120;
  style.background_cd_m2 = 20;
  const ImageRGBA image = render_text_image("Which light is brighter?", style);
  float lowest = 1e9f, highest = -1e9f;
  for (int y = 0; y < image.height_px; ++y)
    for (int x = 0; x < image.width_px; ++x) {
      const float* pixel = image.pixel(x, y);
      EXPECT_EQ(pixel[0], pixel[1]);
      EXPECT_EQ(pixel[0], pixel[2]);
      EXPECT_EQ(pixel[3], 1.0f);
      lowest = std::min(lowest, pixel[0]);
      highest = std::max(highest, pixel[0]);
    }
  EXPECT_FLOAT_EQ(lowest, 20.0f);   // untouched background
  EXPECT_FLOAT_EQ(highest, 120.0f);  // fully covered stem pixels (a stem is about 4 px wide at em 50)
}

TEST(TextImage, WrapsAtSpacesWithinTheWidthAndCentresLines) {
  TextImageStyle style;
  style.line_height_px = 40;
  const ImageRGBA one_line = render_text_image("glare appears brighter", style);
  style.max_width_px = 0.75 * one_line.width_px;  // "glare appears" fits, "brighter" wraps
  const ImageRGBA wrapped = render_text_image("glare appears brighter", style);
  EXPECT_EQ(wrapped.height_px, 2 * 40);
  EXPECT_LE(wrapped.width_px, style.max_width_px);
  // The shorter second line ("brighter") is centred: equal margins within a pixel.
  const InkBox second = ink_box(wrapped, 50, 40, 79);
  EXPECT_NEAR(second.left, wrapped.width_px - 1 - second.right, 2.0);
}

TEST(TextImage, NewlinesBreakLinesAndLinesShareOneBaselineSpacing) {
  TextImageStyle style;
  style.line_height_px = 50;
  const ImageRGBA image = render_text_image("I\nI\nI", style);
  ASSERT_EQ(image.height_px, 150);
  const InkBox first = ink_box(image, 50, 0, 49);
  const InkBox third = ink_box(image, 50, 100, 149);
  EXPECT_EQ(third.bottom - first.bottom, 100);
  EXPECT_EQ(third.top - first.top, 100);
}

TEST(TextImage, AWordWiderThanTheLineIsNotSplit) {
  TextImageStyle style;
  style.line_height_px = 40;
  style.max_width_px = 10;
  const ImageRGBA image = render_text_image("brightness", style);
  EXPECT_EQ(image.height_px, 40);
  EXPECT_GT(image.width_px, 10);
}

TEST(TextImage, InvalidUtf8ShowsAsTheReplacementCharacter) {
  TextImageStyle style;
  const ImageRGBA invalid = render_text_image("a\xC3(b", style);  // truncated two-byte sequence
  const ImageRGBA replaced = render_text_image("a\xEF\xBF\xBD(b", style);
  ASSERT_EQ(invalid.width_px, replaced.width_px);
  EXPECT_EQ(invalid.rgba, replaced.rgba);
  // A valid multi-byte character is one glyph, not its bytes: "é" is as wide as "e" with an accent.
  EXPECT_EQ(render_text_image("\xC3\xA9", style).width_px, render_text_image("e", style).width_px);
}

TEST(TextImage, EmptyTextIsAnEmptyImageAndTinyLinesAreRefused) {
  EXPECT_TRUE(render_text_image("", TextImageStyle{}).empty());
  TextImageStyle tiny;
  tiny.line_height_px = 2;
  EXPECT_THROW(render_text_image("x", tiny), TextError);
}

}  // namespace
}  // namespace glarelab
